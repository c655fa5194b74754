#include "io/vtk_writer.hpp"

#include "measure/measurements.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "io/output_files.hpp"
#include "measure/contact_network.hpp"
#include "measure/displacement.hpp"

namespace geodem {

namespace {

// Collects arrays for the appended-data section and their XML headers.
class AppendedData {
 public:
  void add(const std::string& name, const std::string& type, int components, const void* data,
           std::size_t bytes) {
    xml_ << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\""
         << components << "\" format=\"appended\" offset=\"" << blob_.size() << "\"/>\n";
    const std::uint64_t n = bytes;
    append(&n, sizeof n);
    append(data, bytes);
  }
  std::string take_xml() {
    std::string s = xml_.str();
    xml_.str("");
    return s;
  }
  const std::string& blob() const { return blob_; }

 private:
  void append(const void* p, std::size_t n) { blob_.append(static_cast<const char*>(p), n); }
  std::ostringstream xml_;
  std::string blob_;
};

template <int D, typename V>
std::vector<double> as3(const std::vector<V>& v) {
  std::vector<double> out(3 * v.size(), 0.0);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < D; ++k) out[3 * i + k] = v[i][k];
  return out;
}

// Writes the file: the XML, then the arrays streamed from the blob (no second copy of them).
void write_vtk(const std::string& path, const std::string& type, const std::string& body,
               const AppendedData& data) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
        << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        << body << "<AppendedData encoding=\"raw\">\n_";
    out.write(data.blob().data(), static_cast<std::streamsize>(data.blob().size()));
    out << "\n</AppendedData>\n</VTKFile>\n";
  });
}

// Closes a PolyData piece of lines: its points and connectivity, then writes the file.
void finish_lines(const std::string& path, std::ostringstream& body, AppendedData& data,
                  const std::vector<double>& pts, const std::vector<std::int64_t>& conn,
                  const std::vector<std::int64_t>& offs) {
  data.add("Points", "Float64", 3, pts.data(), pts.size() * sizeof(double));
  body << "<Points>\n" << data.take_xml() << "</Points>\n";
  data.add("connectivity", "Int64", 1, conn.data(), conn.size() * 8);
  data.add("offsets", "Int64", 1, offs.data(), offs.size() * 8);
  body << "<Lines>\n" << data.take_xml() << "</Lines>\n</Piece>\n</PolyData>\n";
  write_vtk(path, "PolyData", body.str(), data);
}

}  // namespace

template <int D>
void write_particles_vtu(const std::string& path, const World<D>& world,
                         const std::vector<typename Dim<D>::Vec>* reference) {
  const auto& P = world.particles;
  const std::size_t n = P.size();
  AppendedData data;
  std::ostringstream body;
  body << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n
       << "\">\n";
  // Point data.
  data.add("radius", "Float64", 1, P.radius.data(), n * sizeof(double));
  const auto vel = as3<D>(P.vel);
  data.add("velocity", "Float64", 3, vel.data(), vel.size() * sizeof(double));
  std::vector<double> w(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if constexpr (D == 2)
      w[3 * i + 2] = P.angvel[i];
    else
      for (int k = 0; k < 3; ++k) w[3 * i + k] = P.angvel[i][k];
  }
  data.add("angular_velocity", "Float64", 3, w.data(), w.size() * sizeof(double));
  const auto f = as3<D>(P.force);
  data.add("force", "Float64", 3, f.data(), f.size() * sizeof(double));
  data.add("id", "UInt32", 1, P.id.data(), n * sizeof(std::uint32_t));
  std::vector<std::uint8_t> mat(P.material.begin(), P.material.end());
  data.add("material", "UInt8", 1, mat.data(), n);
  // Clump of each grain (its stable id; -1: a free grain), so that members can be coloured
  // by clump.
  std::vector<std::int32_t> clump(n, -1);
  for (std::size_t i = 0; i < P.clump.size(); ++i)
    if (P.clump[i] != kNoClump) clump[i] = static_cast<std::int32_t>(world.clumps.id[P.clump[i]]);
  data.add("clump", "Int32", 1, clump.data(), n * sizeof(std::int32_t));
  if (reference) {
    std::vector<double> u(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto d = displacement(world, *reference, i);
      for (int k = 0; k < D; ++k) u[3 * i + k] = d[k];
    }
    data.add("displacement", "Float64", 3, u.data(), u.size() * sizeof(double));
  }
  body << "<PointData Scalars=\"radius\" Vectors=\"velocity\">\n"
       << data.take_xml() << "</PointData>\n";
  const auto x = as3<D>(P.pos);
  data.add("Points", "Float64", 3, x.data(), x.size() * sizeof(double));
  body << "<Points>\n" << data.take_xml() << "</Points>\n";
  std::vector<std::int64_t> conn(n), offs(n);
  for (std::size_t i = 0; i < n; ++i)
    conn[i] = static_cast<std::int64_t>(i), offs[i] = static_cast<std::int64_t>(i + 1);
  std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  data.add("connectivity", "Int64", 1, conn.data(), n * 8);
  data.add("offsets", "Int64", 1, offs.data(), n * 8);
  data.add("types", "UInt8", 1, types.data(), n);
  body << "<Cells>\n" << data.take_xml() << "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
  write_vtk(path, "UnstructuredGrid", body.str(), data);
}

namespace {

// The index of a frame written in pieces (.pvtu, .pvtp): `sections` declares the pieces'
// arrays (PPointData, PCellData, PPoints, PCells), then the pieces' files are listed.
void write_piece_index(const std::string& path, const std::string& type,
                       const std::string& sections, const std::vector<std::string>& pieces) {
  std::ostringstream body;
  body << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
       << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<" << type
       << " GhostLevel=\"0\">\n"
       << sections;
  for (const auto& p : pieces) body << "<Piece Source=\"" << p << "\"/>\n";
  body << "</" << type << ">\n</VTKFile>\n";
  write_file_atomic(path, [&](std::ostream& out) { out << body.str(); });
}

// An array's declaration in an index: name, type, components.
struct PArray {
  const char* name;
  const char* type;
  int components;
};
std::string section(const std::string& tag, const std::string& attributes,
                    const std::vector<PArray>& arrays) {
  std::string s = "<" + tag + attributes + ">\n";
  for (const auto& a : arrays)
    s += std::string("<PDataArray type=\"") + a.type + "\" Name=\"" + a.name +
         "\" NumberOfComponents=\"" + std::to_string(a.components) + "\"/>\n";
  return s + "</" + tag + ">\n";
}

}  // namespace

void write_contacts_pvtp(const std::string& path, const std::vector<std::string>& pieces) {
  // The arrays of write_contacts_vtp.
  write_piece_index(path, "PPolyData",
                    section("PPointData", " Scalars=\"radius\"", {{"radius", "Float64", 1}}) +
                        section("PCellData", " Scalars=\"force\" Vectors=\"normal\"",
                                {{"force", "Float64", 1},
                                 {"normal_force", "Float64", 1},
                                 {"tangential_force", "Float64", 3},
                                 {"tangential_force_magnitude", "Float64", 1},
                                 {"normal", "Float64", 3},
                                 {"overlap", "Float64", 1},
                                 {"bonded", "Int64", 1}}) +
                        section("PPoints", "", {{"Points", "Float64", 3}}),
                    pieces);
}

void write_particles_pvtu(const std::string& path, const std::vector<std::string>& pieces,
                          bool displacement) {
  // The arrays of write_particles_vtu.
  std::vector<PArray> point = {
      {"radius", "Float64", 1}, {"velocity", "Float64", 3}, {"angular_velocity", "Float64", 3},
      {"force", "Float64", 3},  {"id", "UInt32", 1},        {"material", "UInt8", 1},
      {"clump", "Int32", 1}};
  if (displacement) point.push_back({"displacement", "Float64", 3});
  write_piece_index(
      path, "PUnstructuredGrid",
      section("PPointData", " Scalars=\"radius\" Vectors=\"velocity\"", point) +
          section("PPoints", "", {{"Points", "Float64", 3}}) +
          section("PCells", "",
                  {{"connectivity", "Int64", 1}, {"offsets", "Int64", 1}, {"types", "UInt8", 1}}),
      pieces);
}

template <int D>
void write_walls_vtp(const std::string& path, const World<D>& world, double half_size,
                     const typename Dim<D>::Vec* grains_centre) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = world.particles;
  Vec centre = Vec::Zero();
  for (const auto& x : P.pos) centre += x;
  if (!P.pos.empty()) centre /= static_cast<double>(P.pos.size());
  if (grains_centre) centre = *grains_centre;
  std::vector<double> pts;
  std::vector<std::int64_t> conn, offs;
  std::vector<double> force, stress;
  auto point = [&](const Vec& p) {
    for (int k = 0; k < 3; ++k) pts.push_back(k < D ? p[k] : 0.0);
    conn.push_back(static_cast<std::int64_t>(pts.size() / 3 - 1));
  };
  for (const auto& w : world.walls) {
    if (w.kind == WallKind::kSegment) {
      point(w.point);
      point(w.end);
    } else if (w.kind == WallKind::kRectangle) {
      point(w.point);
      point(w.end);
      point(w.end + w.across);
      point(w.point + w.across);
    } else {
      const Vec c = centre - (centre - w.point).dot(w.normal) * w.normal;
      if constexpr (D == 2) {
        const Vec t(-w.normal.y(), w.normal.x());
        point(c - half_size * t);
        point(c + half_size * t);
      } else {
        Vec a = std::abs(w.normal.x()) < 0.9 ? Vec::UnitX() : Vec::UnitY();
        const Vec t1 = (a - a.dot(w.normal) * w.normal).normalized();
        const Vec t2 = w.normal.cross(t1);
        point(c - half_size * t1 - half_size * t2);
        point(c + half_size * t1 - half_size * t2);
        point(c + half_size * t1 + half_size * t2);
        point(c - half_size * t1 + half_size * t2);
      }
    }
    offs.push_back(static_cast<std::int64_t>(conn.size()));
    for (int k = 0; k < 3; ++k) force.push_back(k < D ? w.force[k] : 0.0);
    stress.push_back(w.normal_stress());
  }
  const std::size_t nw = world.walls.size();
  AppendedData data;
  std::ostringstream body;
  const bool lines = D == 2;
  body << "<PolyData>\n<Piece NumberOfPoints=\"" << pts.size() / 3 << "\" NumberOfVerts=\"0\" "
       << "NumberOfLines=\"" << (lines ? nw : 0) << "\" NumberOfStrips=\"0\" NumberOfPolys=\""
       << (lines ? 0 : nw) << "\">\n";
  data.add("force", "Float64", 3, force.data(), force.size() * sizeof(double));
  data.add("normal_stress", "Float64", 1, stress.data(), stress.size() * sizeof(double));
  body << "<CellData Vectors=\"force\">\n" << data.take_xml() << "</CellData>\n";
  data.add("Points", "Float64", 3, pts.data(), pts.size() * sizeof(double));
  body << "<Points>\n" << data.take_xml() << "</Points>\n";
  data.add("connectivity", "Int64", 1, conn.data(), conn.size() * 8);
  data.add("offsets", "Int64", 1, offs.data(), offs.size() * 8);
  const char* tag = lines ? "Lines" : "Polys";
  body << "<" << tag << ">\n" << data.take_xml() << "</" << tag << ">\n</Piece>\n</PolyData>\n";
  write_vtk(path, "PolyData", body.str(), data);
}

template <int D>
void write_cell_vtp(const std::string& path, const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  const auto& h = world.cell.h;
  std::vector<double> pts, stress;
  std::vector<std::int64_t> conn, offs;
  const typename Dim<D>::Tensor sigma = cell_stress(world);
  // Corner c (bits: which edge vectors are added); an edge joins corners one bit apart.
  auto corner = [&](int c) {
    Vec x = Vec::Zero();
    for (int k = 0; k < D; ++k)
      if (c & (1 << k)) x += h.col(k);
    return x;
  };
  for (int c = 0; c < (1 << D); ++c)
    for (int k = 0; k < D; ++k) {
      if (c & (1 << k)) continue;
      for (const Vec& x : {corner(c), corner(c | (1 << k))}) {
        for (int a = 0; a < 3; ++a) pts.push_back(a < D ? x[a] : 0.0);
        conn.push_back(static_cast<std::int64_t>(pts.size() / 3 - 1));
      }
      offs.push_back(static_cast<std::int64_t>(conn.size()));
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) stress.push_back(a < D && b < D ? sigma(a, b) : 0.0);
    }
  AppendedData data;
  std::ostringstream body;
  body << "<PolyData>\n<Piece NumberOfPoints=\"" << pts.size() / 3
       << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << offs.size()
       << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  data.add("stress", "Float64", 9, stress.data(), stress.size() * sizeof(double));
  body << "<CellData Tensors=\"stress\">\n" << data.take_xml() << "</CellData>\n";
  finish_lines(path, body, data, pts, conn, offs);
}

template <int D>
void write_spars_vtp(const std::string& path, const World<D>& world) {
  const auto& S = world.spars;
  std::vector<double> pts, vel, tension, stiffness;
  std::vector<std::int64_t> conn, offs, chain;
  for (std::size_t i = 0; i < S.nodes(); ++i)
    for (int k = 0; k < 3; ++k) {
      pts.push_back(k < D ? S.pos[i][k] : 0.0);
      vel.push_back(k < D ? S.vel[i][k] : 0.0);
    }
  for (std::size_t e = 0; e < S.elements(); ++e) {
    conn.push_back(S.node_a[e]);
    conn.push_back(S.node_b[e]);
    offs.push_back(static_cast<std::int64_t>(conn.size()));
    tension.push_back(S.tension[e]);
    stiffness.push_back(S.stiffness[e]);
    chain.push_back(S.chain_of[e]);
  }
  AppendedData data;
  std::ostringstream body;
  body << "<PolyData>\n<Piece NumberOfPoints=\"" << S.nodes() << "\" NumberOfVerts=\"0\" "
       << "NumberOfLines=\"" << S.elements() << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  data.add("velocity", "Float64", 3, vel.data(), vel.size() * sizeof(double));
  body << "<PointData Vectors=\"velocity\">\n" << data.take_xml() << "</PointData>\n";
  data.add("tension", "Float64", 1, tension.data(), tension.size() * sizeof(double));
  data.add("stiffness_J", "Float64", 1, stiffness.data(), stiffness.size() * sizeof(double));
  data.add("chain", "Int64", 1, chain.data(), chain.size() * 8);
  body << "<CellData Scalars=\"tension\">\n" << data.take_xml() << "</CellData>\n";
  finish_lines(path, body, data, pts, conn, offs);
}

template <int D>
void write_contacts_vtp(const std::string& path, const World<D>& world) {
  const auto& P = world.particles;
  const auto c = contact_network(world);
  std::vector<double> pts = as3<D>(P.pos), normal = as3<D>(c.normal),
                      ft = as3<D>(c.tangential_force), ft_norm, force;
  std::vector<std::int64_t> conn, offs, bonded;
  for (std::size_t k = 0; k < c.size(); ++k) {
    conn.push_back(c.i[k]), conn.push_back(c.j[k]);
    offs.push_back(static_cast<std::int64_t>(conn.size()));
    const double t = c.tangential_force[k].norm();
    ft_norm.push_back(t);
    force.push_back(std::sqrt(c.normal_force[k] * c.normal_force[k] + t * t));
    bonded.push_back(c.bonded[k]);
  }
  AppendedData data;
  std::ostringstream body;
  body << "<PolyData>\n<Piece NumberOfPoints=\"" << P.size() << "\" NumberOfVerts=\"0\" "
       << "NumberOfLines=\"" << c.size() << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  data.add("radius", "Float64", 1, P.radius.data(), P.radius.size() * sizeof(double));
  body << "<PointData Scalars=\"radius\">\n" << data.take_xml() << "</PointData>\n";
  data.add("force", "Float64", 1, force.data(), force.size() * sizeof(double));
  data.add("normal_force", "Float64", 1, c.normal_force.data(),
           c.normal_force.size() * sizeof(double));
  data.add("tangential_force", "Float64", 3, ft.data(), ft.size() * sizeof(double));
  data.add("tangential_force_magnitude", "Float64", 1, ft_norm.data(),
           ft_norm.size() * sizeof(double));
  data.add("normal", "Float64", 3, normal.data(), normal.size() * sizeof(double));
  data.add("overlap", "Float64", 1, c.overlap.data(), c.overlap.size() * sizeof(double));
  data.add("bonded", "Int64", 1, bonded.data(), bonded.size() * 8);
  body << "<CellData Scalars=\"force\" Vectors=\"normal\">\n" << data.take_xml() << "</CellData>\n";
  finish_lines(path, body, data, pts, conn, offs);
}

void PvdIndex::add(double time, const std::string& file, int part) {
  entries_.push_back({time, file, part});
}

void PvdIndex::write() const {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& e : entries_)
    s << "  <DataSet timestep=\"" << format_number(e.time) << "\" part=\"" << e.part << "\" file=\""
      << e.file << "\"/>\n";
  s << "</Collection>\n</VTKFile>\n";
  write_file_atomic(path_, s.str());
}

template void write_particles_vtu<2>(const std::string&, const World<2>&,
                                     const std::vector<Dim<2>::Vec>*);
template void write_particles_vtu<3>(const std::string&, const World<3>&,
                                     const std::vector<Dim<3>::Vec>*);
template void write_walls_vtp<2>(const std::string&, const World<2>&, double, const Dim<2>::Vec*);
template void write_walls_vtp<3>(const std::string&, const World<3>&, double, const Dim<3>::Vec*);
template void write_cell_vtp<2>(const std::string&, const World<2>&);
template void write_cell_vtp<3>(const std::string&, const World<3>&);
template void write_spars_vtp<2>(const std::string&, const World<2>&);
template void write_spars_vtp<3>(const std::string&, const World<3>&);
template void write_contacts_vtp<2>(const std::string&, const World<2>&);
template void write_contacts_vtp<3>(const std::string&, const World<3>&);

}  // namespace geodem
