#include "broadphase/periodic_search.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "base/error.hpp"
#include "base/parallel.hpp"
#include "clumps/clump_dynamics.hpp"

namespace geodem {

namespace {

// The whole edge vectors to take off x to bring it into the cell: floor(h^-1 x).
template <int D>
CellImage outside_by(const typename Dim<D>::Tensor& h_inv, const typename Dim<D>::Vec& x) {
  const typename Dim<D>::Vec s = h_inv * x;
  CellImage c;
  for (int k = 0; k < D; ++k) c.m[k] = static_cast<std::int8_t>(std::floor(s[k]));
  return c;
}

}  // namespace

template <int D>
void wrap_into_cell(World<D>& world) {
  auto& P = world.particles;
  auto& C = world.clumps;
  const auto& cell = world.cell;
  const typename Dim<D>::Tensor h_inv = cell.h.inverse();
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.member(i)) continue;
    const CellImage c = outside_by<D>(h_inv, P.pos[i]);
    if (!c.home()) P.pos[i] -= cell.shift(c);
  }
  bool moved = false;
  for (std::size_t c = 0; c < C.size(); ++c) {
    const CellImage m = outside_by<D>(h_inv, C.pos[c]);
    if (m.home()) continue;
    C.pos[c] -= cell.shift(m);
    moved = true;
  }
  if (moved) place_members(world);
}

namespace {

// The grains binned in the cell's fractional coordinates, bins at least a search reach wide
// across the faces, filled by a counting sort. Kept between builds, one per calling thread.
struct PeriodicBins {
  std::array<int, 3> nb{1, 1, 1};
  std::vector<std::array<int, 3>> bin_of;
  std::vector<CellImage> outside;  // a clump member beyond the faces: by how many edges
  std::vector<std::uint32_t> bin_start, sorted, fill;
  std::size_t index(const std::array<int, 3>& b) const {
    return static_cast<std::size_t>((b[2] * nb[1] + b[1]) * nb[0] + b[0]);
  }
};

template <int D>
PeriodicBins& bin_grains(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  static thread_local PeriodicBins bins;
  PeriodicBins& g = bins;
  const auto& P = world.particles;
  auto& cell = world.cell;
  const std::size_t n = P.size();
  double rmax = 0.0;
  for (double r : P.radius) rmax = std::max(rmax, r);
  // A decomposed cell (domain/slab_domain.hpp): the whole domain's, so that every rank takes
  // the same reach (the list's expiry depends on it).
  if (world.domain) rmax = -world.domain->min_over_ranks(-rmax);
  const double reach = 2.0 * rmax + world.nlist.skin;
  cell.reach_at_build = reach;
  const Vec widths = cell.widths();
  g.nb = {1, 1, 1};
  for (int k = 0; k < D; ++k) {
    g.nb[k] = static_cast<int>(std::floor(widths[k] / reach));
    if (g.nb[k] < 3)
      throw InputError("", 0, "cell",
                       "the periodic cell is " + std::to_string(widths[k]) +
                           " m across its faces " + std::to_string(k) +
                           ", less than three times the largest diameter plus the skin (" +
                           std::to_string(3.0 * reach) + " m): make the cell larger");
    // Few grains in a large cell: bins of about one grain each are enough (n^(1/D) per axis).
    g.nb[k] =
        std::min(g.nb[k], 4 * static_cast<int>(std::pow(static_cast<double>(n), 1.0 / D)) + 8);
  }
  const typename Dim<D>::Tensor h_inv = cell.h.inverse();
  g.bin_of.assign(n, {0, 0, 0});
  g.outside.assign(n, CellImage{});
  const std::size_t nbins = static_cast<std::size_t>(g.nb[0]) * g.nb[1] * g.nb[2];
  g.bin_start.assign(nbins + 1, 0);
  // A clump member may lie beyond the faces (its clump was moved back by its centre): it is
  // binned where its image inside the cell is, and remembers by how many edges it is out.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec s = h_inv * P.pos[i];
    for (int k = 0; k < D; ++k) {
      const double whole = std::floor(s[k]);
      g.outside[i].m[k] = static_cast<std::int8_t>(whole);
      g.bin_of[i][k] =
          std::clamp(static_cast<int>(std::floor((s[k] - whole) * g.nb[k])), 0, g.nb[k] - 1);
    }
    ++g.bin_start[g.index(g.bin_of[i]) + 1];
  }
  for (std::size_t b = 0; b < nbins; ++b) g.bin_start[b + 1] += g.bin_start[b];
  g.sorted.resize(n);
  g.fill.assign(g.bin_start.begin(), g.bin_start.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    g.sorted[g.fill[g.index(g.bin_of[i])]++] = static_cast<std::uint32_t>(i);
  return g;
}

}  // namespace

template <int D>
std::vector<std::uint32_t> periodic_spatial_order(World<D>& world) {
  return bin_grains(world).sorted;
}

template <int D>
void list_periodic_pairs(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = world.particles;
  auto& L = world.nlist;
  const auto& cell = world.cell;
  const std::size_t n = P.size();
  const PeriodicBins& g = bin_grains(world);
  const auto& nb = g.nb;
  const auto& bin_of = g.bin_of;
  const auto& outside = g.outside;
  const auto& bin_start = g.bin_start;
  const auto& sorted = g.sorted;
  auto index = [&g](const std::array<int, 3>& b) { return g.index(b); };

  const bool clumps = !P.clump.empty();
  const int zr = D == 3 ? 1 : 0;
  const std::uint8_t* flags = P.flags.data();
  // Calls pair(j, image) for each grain j > i within reach of grain i, in bin order. A ghost
  // (domain/slab_domain.hpp) pairs with the rank's own grains only.
  auto scan = [&](std::size_t i, auto&& pair) {
    const Vec xi = P.pos[i];
    const bool ghost = flags[i] & kGhost;
    const double ri = P.radius[i] + L.skin;
    const std::uint32_t ci = clumps ? P.clump[i] : kNoClump;
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::array<int, 3> off{dx, dy, dz};
          std::array<int, 3> b{0, 0, 0};
          CellImage image;
          for (int k = 0; k < D; ++k) {
            b[k] = bin_of[i][k] + off[k];
            if (b[k] < 0) {
              b[k] += nb[k];
              image.m[k] = -1;
            } else if (b[k] >= nb[k]) {
              b[k] -= nb[k];
              image.m[k] = 1;
            }
          }
          const std::size_t bin = index(b);
          for (std::uint32_t s = bin_start[bin]; s < bin_start[bin + 1]; ++s) {
            const std::uint32_t j = sorted[s];
            if (j <= i) continue;
            if (ci != kNoClump && P.clump[j] == ci) continue;  // members of one clump
            if (ghost && (flags[j] & kGhost)) continue;
            // The bins hold the grains' images inside the cell: from grain i's own position,
            // grain j is seen through the bins' image plus i's and less j's offset.
            CellImage seen = image;
            for (int k = 0; k < D; ++k)
              seen.m[k] = static_cast<std::int8_t>(image.m[k] + outside[i].m[k] - outside[j].m[k]);
            const double r = ri + P.radius[j];
            if ((P.pos[j] + cell.shift(seen) - xi).squaredNorm() < r * r) pair(j, seen);
          }
        }
  };
  // A row sorted by partner (a partner has one image within reach: the cell is at least three
  // reaches across), the image moving with it.
  auto sort_row = [&L](std::size_t b, std::size_t e) {
    for (std::size_t x = b + 1; x < e; ++x)
      for (std::size_t y = x; y > b && L.other[y - 1] > L.other[y]; --y) {
        std::swap(L.other[y - 1], L.other[y]);
        std::swap(L.image[y - 1], L.image[y]);
      }
  };
  L.start.assign(n + 1, 0);
  L.other.clear();
  L.image.clear();
  const bool par = world.threads > 1 && n >= kParallelMin;
  if (!par) {
    // One thread: a single pass appending rows gives the same rows at half the cost.
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t row_begin = L.other.size();
      scan(i, [&](std::uint32_t j, const CellImage& m) {
        L.other.push_back(j);
        L.image.push_back(m);
      });
      sort_row(row_begin, L.other.size());
      L.start[i + 1] = static_cast<std::uint32_t>(L.other.size());
    }
    return;
  }
  // Several threads: count every row's pairs, then fill each row at its offset; the rows
  // are the same whatever the threads.
  const auto rows = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for num_threads(world.threads) schedule(static)
  for (std::ptrdiff_t ii = 0; ii < rows; ++ii) {
    std::uint32_t count = 0;
    scan(static_cast<std::size_t>(ii), [&count](std::uint32_t, const CellImage&) { ++count; });
    L.start[static_cast<std::size_t>(ii) + 1] = count;
  }
  for (std::size_t i = 0; i < n; ++i) L.start[i + 1] += L.start[i];
  L.other.resize(L.start[n]);
  L.image.resize(L.start[n]);
#pragma omp parallel for num_threads(world.threads) schedule(static)
  for (std::ptrdiff_t ii = 0; ii < rows; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    std::size_t k = L.start[i];
    scan(i, [&](std::uint32_t j, const CellImage& m) {
      L.other[k] = j;
      L.image[k] = m;
      ++k;
    });
    sort_row(L.start[i], k);
  }
}

template void wrap_into_cell<2>(World<2>&);
template void wrap_into_cell<3>(World<3>&);
template void list_periodic_pairs<2>(World<2>&);
template void list_periodic_pairs<3>(World<3>&);
template std::vector<std::uint32_t> periodic_spatial_order<2>(World<2>&);
template std::vector<std::uint32_t> periodic_spatial_order<3>(World<3>&);

}  // namespace geodem
