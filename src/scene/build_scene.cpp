#include "scene/build_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "base/error.hpp"
#include "base/random.hpp"
#include "clumps/grain_mix.hpp"
#include "io/output_files.hpp"
#include "particles/random_cloud.hpp"
#include "scene/input_overlaps.hpp"

namespace geodem {

namespace {

std::uint16_t material_index(const std::vector<Material>& mats, const std::string& name) {
  for (std::size_t i = 0; i < mats.size(); ++i)
    if (mats[i].name == name) return static_cast<std::uint16_t>(i);
  throw std::logic_error("unknown material " + name);  // names were checked when reading
}

// Number of rows with data (not blank, not only a comment) in a text file.
std::size_t count_data_rows(const std::string& path) {
  std::ifstream in(path);
  std::size_t rows = 0;
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first != std::string::npos && line[first] != '#') ++rows;
  }
  return rows;
}

}  // namespace

namespace {

// Reads whitespace- or comma-separated rows; '#' starts a comment.
template <int D, typename Add>
void read_particle_file(const ParticleFileSpec& spec, std::size_t index,
                        const std::string& scenario, std::size_t materials, Add&& add) {
  using Vec = typename Dim<D>::Vec;
  std::ifstream in(spec.path);
  if (!in)
    throw InputError(scenario, 0, "particle_files." + std::to_string(index) + ".file",
                     "cannot read " + spec.path);
  std::string line;
  int lineno = 0;
  std::vector<double> values;
  // Names the scenario, its key and the data file's line.
  auto bad_row = [&](const std::string& what) {
    return InputError(scenario, 0, "particle_files." + std::to_string(index),
                      spec.path + ":" + std::to_string(lineno) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    values.clear();
    for (std::string tok; ls >> tok;) {
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end == tok.c_str() || *end != '\0' || !std::isfinite(v))
        throw bad_row("expected numbers, got '" + tok + "'");
      values.push_back(v);
    }
    if (values.empty()) continue;
    if (values.size() != spec.columns.size())
      throw bad_row("expected " + std::to_string(spec.columns.size()) + " columns, got " +
                    std::to_string(values.size()));
    Vec x = Vec::Zero(), v = Vec::Zero();
    double r = spec.radius;
    long long material = -1;  // from the spec
    for (std::size_t c = 0; c < values.size(); ++c) {
      const std::string& name = spec.columns[c];
      if (name == "x")
        x[0] = values[c];
      else if (name == "y")
        x[1] = values[c];
      else if (name == "z" && D == 3)
        x[D - 1] = values[c];
      else if (name == "vx")
        v[0] = values[c];
      else if (name == "vy")
        v[1] = values[c];
      else if (name == "vz" && D == 3)
        v[D - 1] = values[c];
      else if (name == "radius")
        r = values[c];
      else if (name == "material") {
        if (values[c] != std::floor(values[c]) || values[c] < 0.0 ||
            values[c] >= static_cast<double>(materials))
          throw bad_row("material must be a 0-based index of the scene's " +
                        std::to_string(materials) + " [[materials]], got " +
                        format_number(values[c]));
        material = static_cast<long long>(values[c]);
      }
    }
    if (!(r > 0.0)) throw bad_row("radius must be positive");
    add(x, r, v, material, lineno);
  }
}

}  // namespace

template <int D>
std::vector<Wall<D>> walls_of(const WallSpec& w, const std::vector<Material>& materials) {
  std::vector<Wall<D>> out;
  auto add = [&](Wall<D> wall) {
    wall.material = material_index(materials, w.material);
    wall.velocity = to_vec<D>(w.velocity);
    wall.area = w.area;
    out.push_back(wall);
  };
  Wall<D> wall;
  wall.name = w.name;
  if (w.type == "plane") {
    wall.kind = WallKind::kPlane;
    wall.point = to_vec<D>(w.point);
    wall.normal = to_vec<D>(w.normal).normalized();
    add(wall);
  } else if (w.type == "segment") {
    wall.kind = WallKind::kSegment;
    wall.point = to_vec<D>(w.from);
    wall.end = to_vec<D>(w.to);
    add(wall);
  } else {
    // A polyline: segment k owns its start vertex; the open end's last vertex is
    // owned by the last segment.
    std::vector<List> pts = w.points;
    if (w.closed) pts.push_back(pts.front());
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      Wall<D> seg;
      seg.name = w.name + "_" + std::to_string(k);
      seg.kind = WallKind::kSegment;
      seg.point = to_vec<D>(pts[k]);
      seg.end = to_vec<D>(pts[k + 1]);
      seg.owns_end_vertex = !w.closed && k + 2 == pts.size();
      add(seg);
    }
  }
  return out;
}

template <int D>
void add_cloud(const SceneSettings& s, const CloudSpec& cl, const std::string& key, World<D>& world,
               Random& rng, std::vector<Sphere<D>>& placed) {
  using Vec = typename Dim<D>::Vec;
  const Vec lo = to_vec<D>(cl.lo), hi = to_vec<D>(cl.hi);
  if (cl.shape != "sphere" && cl.shape != "disc") {
    // Clumps: random orientations; bounding spheres kept apart.
    GrainSpec spec;
    spec.templates = s.templates;
    spec.kinds[0].shape = cl.shape;
    const auto m = material_index(s.materials, cl.material);
    try {
      add_random_grains<D>(world, resolve_kinds<D>(spec), lo, hi, cl.count, cl.porosity, cl.fuzz,
                           s.materials[m].density, m, rng, to_vec<D>(cl.velocity), cl.radius,
                           &placed);
    } catch (const std::runtime_error& e) {
      throw InputError(s.file, 0, key, e.what());
    }
    return;
  }
  const double mean = cl.radius > 0.0 ? cl.radius
                                      : mean_radius_for_porosity<D>((hi - lo).prod(), cl.count,
                                                                    cl.porosity, cl.fuzz);
  // Solid fraction asked for: beyond what random placement can reach, say so at once
  // rather than after trying (mean volume with radii uniform in mean (1 +- fuzz)).
  const double f2 = cl.fuzz * cl.fuzz;
  const double grain_volume = Dim<D>::volume(mean) * (D == 3 ? 1.0 + f2 : 1.0 + f2 / 3.0);
  const double solid = static_cast<double>(cl.count) * grain_volume / (hi - lo).prod();
  // Random sequential placement jams at about 38 % solid (spheres), 55 % (discs).
  if (solid > (D == 3 ? 0.40 : 0.56))
    throw InputError(s.file, 0, key,
                     "too dense: " + std::to_string(cl.count) + " grains of mean radius " +
                         format_number(mean) + " m would fill " +
                         format_number(std::round(solid * 1000.0) / 10.0) +
                         " % of the cloud's box; random placement jams near 38 % (spheres) or 55 % "
                         "(discs): enlarge the box, or lower the count or the radius");
  std::vector<Sphere<D>> grains;
  try {
    grains = random_cloud<D>(lo, hi, cl.count, mean, cl.fuzz, rng, placed);
  } catch (const std::runtime_error& e) {
    throw InputError(s.file, 0, key, e.what());
  }
  const auto m = material_index(s.materials, cl.material);
  for (const auto& g : grains) {
    world.particles.add(g.centre, g.radius, s.materials[m].density, m, to_vec<D>(cl.velocity));
    placed.push_back(g);
  }
}

template <int D>
void add_chain_spec(const ChainSpec& c, const SceneSettings& s, World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  std::vector<Vec> nodes = {to_vec<D>(c.points.front())};
  for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Vec a = to_vec<D>(c.points[k]), b = to_vec<D>(c.points[k + 1]);
    const int parts =
        c.element_length > 0.0
            ? std::max(1, static_cast<int>(std::ceil((b - a).norm() / c.element_length - 1e-9)))
            : 1;
    for (int j = 1; j <= parts; ++j) nodes.push_back(a + (b - a) * (double(j) / parts));
  }
  const auto count = static_cast<long long>(nodes.size());
  for (long long h : c.held)
    if (h < -count || h >= count)
      throw InputError(s.file, 0, "chains." + c.name + ".held",
                       "node " + std::to_string(h) + " does not exist (the chain has " +
                           std::to_string(count) + " nodes)");
  const std::size_t first = world.spars.nodes();
  world.spars.add_chain(c.name, nodes, c.stiffness, c.mass_per_length, c.thickness,
                        material_index(s.materials, c.material), c.bending);
  for (long long h : c.held) {
    const std::size_t i = first + static_cast<std::size_t>(h < 0 ? count + h : h);
    world.spars.flags[i] = kNodeDriven;
    world.spars.vel[i] = to_vec<D>(c.velocity);
  }
  world.rebuild_needed = true;
}

template <int D>
Sphere<D> add_clump_spec(const ClumpSpec& c, const SceneSettings& s, World<D>& world) {
  const auto m = material_index(s.materials, c.material);
  typename Dim<D>::Orient q;
  const double angle = c.angle_deg * std::numbers::pi / 180.0;
  if constexpr (D == 2)
    q = angle;
  else
    q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, to_vec<3>(c.axis).normalized()));
  const auto shape = resolve_shape<D>(c.shape, s.templates);
  add_clump(world, shape, to_vec<D>(c.position), q, c.scale, s.materials[m].density, m,
            to_vec<D>(c.velocity));
  world.rebuild_needed = true;
  return {to_vec<D>(c.position), c.scale * shape.bounding_radius};
}

template <int D>
void build_world(const SceneSettings& s, World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  world.materials = s.materials;
  world.gravity = to_vec<D>(s.gravity);
  world.local_damping = s.local_damping;
  world.overlap_limit = s.max_overlap;
  world.skin_factor = s.skin;
  world.sort_interval = s.sort_interval;
  world.auto_dt = s.time.step <= 0.0;
  world.dt = s.time.step;
  world.dt_safety = s.time.safety;
  world.dt_update_interval = s.time.update_interval;

  for (const auto& w : s.walls)
    for (const auto& wall : walls_of<D>(w, s.materials)) world.walls.push_back(wall);
  for (const auto& c : s.chains) add_chain_spec(c, s, world);
  world.resolve_pair_laws();
  for (const auto& p : s.pairs) {
    const auto a = material_index(s.materials, p.a), b = material_index(s.materials, p.b);
    for (auto* law : {&world.pair_laws[a * s.materials.size() + b],
                      &world.pair_laws[b * s.materials.size() + a]}) {
      if (p.friction) law->mu = *p.friction;
      if (p.restitution) law->beta = damping_ratio(*p.restitution);
      if (p.restitution && law->law == LawKind::kHertz)
        law->hertz_damp = PairLaw::hertz_damping(law->beta);
      if (p.kn)
        law->constant_stiffness = true, law->kn = *p.kn, law->kt = p.kt.value_or(0.5 * *p.kn);
    }
  }

  // Reserve the grain arrays once: growing them by doubling would leave up to twice the
  // memory they need.
  std::size_t total = s.particles.size();
  for (const auto& c : s.clouds) total += c.count;
  for (const auto& f : s.particle_files) total += count_data_rows(f.path);
  world.particles.reserve(total);
  std::vector<Sphere<D>> placed;
  placed.reserve(total);
  // Where each given grain was given (a particle file and its line, or a [[particles]] entry),
  // for messages: 8 bytes a grain, the text made for an error only.
  struct GivenAt {
    std::uint32_t file, at;
  };
  constexpr std::uint32_t kEntry = ~std::uint32_t{0};
  std::vector<GivenAt> source;
  source.reserve(total);
  for (const auto& p : s.particles) {
    source.push_back({kEntry, static_cast<std::uint32_t>(source.size())});
    const auto m = material_index(s.materials, p.material);
    typename Dim<D>::Rot w;
    if constexpr (D == 2)
      w = p.angular_velocity[0];
    else
      w = Vec(p.angular_velocity[0], p.angular_velocity[1], p.angular_velocity[2]);
    world.particles.add(to_vec<D>(p.position), p.radius, s.materials[m].density, m,
                        to_vec<D>(p.velocity), w, p.fixed);
    placed.push_back({to_vec<D>(p.position), p.radius});
  }
  for (std::size_t f = 0; f < s.particle_files.size(); ++f) {
    const auto& spec = s.particle_files[f];
    const auto m = material_index(s.materials, spec.material);
    read_particle_file<D>(
        spec, f, s.file, s.materials.size(),
        [&](const Vec& x, double r, const Vec& v, long long mat, int line) {
          const auto mi = mat < 0 ? m : static_cast<std::uint16_t>(mat);
          world.particles.add(x, r, s.materials[mi].density, mi, v);
          placed.push_back({x, r});
          source.push_back({static_cast<std::uint32_t>(f), static_cast<std::uint32_t>(line)});
        });
  }
  reject_input_overlaps<D>(
      placed,
      [&](std::size_t k) {
        const GivenAt g = source[k];
        return g.file == kEntry ? "particles." + std::to_string(g.at)
                                : s.particle_files[g.file].path + ":" + std::to_string(g.at);
      },
      s.max_overlap, s.file);
  Random rng(s.seed);
  for (const auto& c : s.clumps) placed.push_back(add_clump_spec(c, s, world));
  for (std::size_t c = 0; c < s.clouds.size(); ++c)
    add_cloud(s, s.clouds[c], "clouds." + std::to_string(c), world, rng, placed);
}

template void build_world<2>(const SceneSettings&, World<2>&);
template void add_chain_spec<2>(const ChainSpec&, const SceneSettings&, World<2>&);
template void add_chain_spec<3>(const ChainSpec&, const SceneSettings&, World<3>&);
template Sphere<2> add_clump_spec<2>(const ClumpSpec&, const SceneSettings&, World<2>&);
template Sphere<3> add_clump_spec<3>(const ClumpSpec&, const SceneSettings&, World<3>&);
template void build_world<3>(const SceneSettings&, World<3>&);
template std::vector<Wall<2>> walls_of<2>(const WallSpec&, const std::vector<Material>&);
template std::vector<Wall<3>> walls_of<3>(const WallSpec&, const std::vector<Material>&);
template void add_cloud<2>(const SceneSettings&, const CloudSpec&, const std::string&, World<2>&,
                           Random&, std::vector<Sphere<2>>&);
template void add_cloud<3>(const SceneSettings&, const CloudSpec&, const std::string&, World<3>&,
                           Random&, std::vector<Sphere<3>>&);

}  // namespace geodem
