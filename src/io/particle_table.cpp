#include "io/particle_table.hpp"

#include <cstdio>

#include "io/output_files.hpp"

namespace geodem {

std::vector<std::string> particle_table_columns(int dimension) {
  return dimension == 3
             ? std::vector<std::string>{"id", "x", "y", "z", "radius", "vx", "vy", "vz", "material"}
             : std::vector<std::string>{"id", "x", "y", "radius", "vx", "vy", "material"};
}

template <int D>
void write_particle_table(const std::string& path, const World<D>& world,
                          const std::vector<Material>& materials) {
  const auto& P = world.particles;
  std::string text = "# grains at time " + format_number(world.time) + " s, step " +
                     std::to_string(world.step) + "; material: 0-based index of";
  for (std::size_t m = 0; m < materials.size(); ++m)
    text += (m ? ", " : " ") + std::to_string(m) + " = " + materials[m].name;
  text += "\n# clump members are listed as single grains\n";
  const auto cols = particle_table_columns(D);
  text += "# columns:";
  for (const auto& c : cols) text += " " + c;
  text += "\n";
  // Streamed in blocks of rows: a table of a million grains (200 MB of text) is never held
  // in memory, where it would be the run's peak.
  write_file_atomic(path, [&](std::ostream& out) {
    out << text;
    text.clear();
    char buf[64];
    auto put = [&](double v, char sep) {
      std::snprintf(buf, sizeof buf, "%.17g%c", v, sep);
      text += buf;
    };
    for (std::size_t i = 0; i < P.size(); ++i) {
      text += std::to_string(P.id[i]) + ",";
      for (int k = 0; k < D; ++k) put(P.pos[i][k], ',');
      put(P.radius[i], ',');
      for (int k = 0; k < D; ++k) put(P.vel[i][k], ',');
      text += std::to_string(P.material[i]) + "\n";
      if (text.size() >= (1u << 16)) {
        out << text;
        text.clear();
      }
    }
    out << text;
  });
}

template void write_particle_table<2>(const std::string&, const World<2>&,
                                      const std::vector<Material>&);
template void write_particle_table<3>(const std::string&, const World<3>&,
                                      const std::vector<Material>&);

}  // namespace geodem
