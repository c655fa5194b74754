#include "broadphase/neighbour_search.hpp"

#include "base/heap_trim.hpp"
#include "base/parallel.hpp"
#include "broadphase/list_history.hpp"
#include "broadphase/periodic_search.hpp"
#include "clumps/clump_dynamics.hpp"
#include "structures/spar_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace geodem {

namespace {

template <int D>
struct Grid {
  using Vec = typename Dim<D>::Vec;
  Vec lo;
  double inv_cell = 1.0;
  std::array<int, 3> dims{1, 1, 1};
  std::vector<std::uint32_t> cell_start;  // per cell, into `sorted`
  std::vector<std::uint32_t> sorted;      // grain indices grouped by cell
  std::vector<std::uint32_t> cell_of;

  int coord(const Vec& x, int k) const {
    const int c = static_cast<int>(std::floor((x[k] - lo[k]) * inv_cell));
    return std::clamp(c, 0, dims[k] - 1);  // clamping keeps neighbours adjacent
  }
  std::uint32_t cell_index(const std::array<int, 3>& c) const {
    return static_cast<std::uint32_t>((c[2] * dims[1] + c[1]) * dims[0] + c[0]);
  }
};

// Renumbers grains in the order `order` (new k = old order[k]) and rewrites the
// old neighbour rows in the new numbering so their history merges as usual. The
// rewritten rows are assembled in `scratch` (the list being rebuilt, whose arrays
// are free at this point) and copied back into `old`: each keeps its arrays, the list
// the room of every pair within the skin and `old` that of the touching ones.
template <int D>
void renumber(World<D>& world, NeighbourList<D>& old, NeighbourList<D>& scratch, bool have_old,
              const std::vector<std::uint32_t>& order) {
  using Spring = TangentSpring<D>;
  const std::size_t n = order.size();
  world.particles.permute(order);
  sort_clumps_by_members(world);
  if (!have_old) return;
  static thread_local std::vector<std::uint32_t> inv, fill;
  inv.resize(n);
  for (std::size_t k = 0; k < n; ++k) inv[order[k]] = static_cast<std::uint32_t>(k);
  // Grain-grain rows: each pair goes to the row of its new lower index; the spring
  // is the force on the higher-index grain, so it is seen from the other side when the
  // roles swap.
  auto& start = scratch.start;
  start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = old.start[i]; k < old.start[i + 1]; ++k)
      ++start[std::min(inv[i], inv[old.other[k]]) + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  const bool extras = world.contact_extras && old.extra.size() == old.other.size() &&
                      old.wall_extra.size() == old.wall.size();
  scratch.other.resize(old.other.size());
  scratch.spring.resize(old.other.size());
  scratch.extra.resize(extras ? old.other.size() : 0);
  fill.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = old.start[i]; k < old.start[i + 1]; ++k) {
      const std::uint32_t a = inv[i], b = inv[old.other[k]];
      const std::uint32_t row = std::min(a, b), slot = fill[row]++;
      scratch.other[slot] = std::max(a, b);
      scratch.spring[slot] = a < b ? old.spring[k] : spring_from_other_body<D>(old.spring[k]);
      if (extras) {
        auto e = old.extra[k];
        // The moment on the new body 2 is the old one reversed, roll + twist n with the
        // normal reversed too: the rolling part changes sign, the twist value does not.
        if (a > b) e.roll = -e.roll;
        scratch.extra[slot] = e;
      }
    }
  for (std::size_t i = 0; i < n; ++i)
    sort_row_by_partner(scratch.other.data(), scratch.spring.data(),
                        extras ? scratch.extra.data() : nullptr, start[i], start[i + 1]);
  // Grain-wall and grain-spar rows keep their entries; only the rows move.
  auto move_rows = [&](const std::vector<std::uint32_t>& o_start,
                       const std::vector<std::uint32_t>& o_idx, const std::vector<Spring>& o_spring,
                       std::vector<std::uint32_t>& s_start, std::vector<std::uint32_t>& s_idx,
                       std::vector<Spring>& s_spring, const std::vector<ContactExtra<D>>* o_extra,
                       std::vector<ContactExtra<D>>* s_extra) {
    if (o_start.size() != n + 1) return;
    s_start.assign(n + 1, 0);
    s_idx.resize(o_idx.size());
    s_spring.resize(o_idx.size());
    if (s_extra) s_extra->resize(o_idx.size());
    for (std::size_t k = 0; k < n; ++k)
      s_start[k + 1] = s_start[k] + (o_start[order[k] + 1] - o_start[order[k]]);
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t src = o_start[order[k]];
      const std::uint32_t len = s_start[k + 1] - s_start[k];
      for (std::uint32_t m = 0; m < len; ++m) {
        s_idx[s_start[k] + m] = o_idx[src + m];
        s_spring[s_start[k] + m] = o_spring[src + m];
        if (s_extra) (*s_extra)[s_start[k] + m] = (*o_extra)[src + m];
      }
    }
  };
  scratch.wall_extra.resize(0);
  move_rows(old.wall_start, old.wall, old.wall_spring, scratch.wall_start, scratch.wall,
            scratch.wall_spring, extras ? &old.wall_extra : nullptr,
            extras ? &scratch.wall_extra : nullptr);
  scratch.spar_start.clear();
  move_rows(old.spar_start, old.spar, old.spar_spring, scratch.spar_start, scratch.spar,
            scratch.spar_spring, nullptr, nullptr);
  old.copy_rows(scratch);
}

// Grain-spar element pairs: each element visits the grid cells its reach covers (its
// bounding box grown by the largest grain radius, its half thickness and the skin), so
// the search stays O(N) however long the chain. Pairs are bucketed by grain (a
// counting sort); elements are visited in order, so each row is sorted by element.
template <int D>
void list_spar_pairs(World<D>& world, const Grid<D>& g, double rmax) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = world.particles;
  const auto& S = world.spars;
  auto& L = world.nlist;
  const std::size_t n = P.size();
  static thread_local std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.clear();
  for (std::size_t e = 0; e < S.elements(); ++e) {
    const Vec a = S.pos[S.node_a[e]], b = S.pos[S.node_b[e]];
    const double reach = rmax + S.half_thickness[e] + L.skin;
    std::array<int, 3> c0{0, 0, 0}, c1{0, 0, 0};
    for (int k = 0; k < D; ++k) {
      Vec lo = a.cwiseMin(b), hi = a.cwiseMax(b);
      lo[k] -= reach;
      hi[k] += reach;
      c0[k] = g.coord(lo, k);
      c1[k] = g.coord(hi, k);
    }
    for (int cz = c0[2]; cz <= c1[2]; ++cz)
      for (int cy = c0[1]; cy <= c1[1]; ++cy)
        for (int cx = c0[0]; cx <= c1[0]; ++cx) {
          const std::uint32_t cell = g.cell_index({cx, cy, cz});
          for (std::uint32_t s = g.cell_start[cell]; s < g.cell_start[cell + 1]; ++s) {
            const std::uint32_t j = g.sorted[s];
            if (P.flags[j] & kGhost) continue;  // its owner computes its contacts
            const double t = std::clamp(spar_parameter(S, e, P.pos[j]), 0.0, 1.0);
            const Vec q = (1.0 - t) * a + t * b;
            const double r = P.radius[j] + S.half_thickness[e] + L.skin;
            if ((q - P.pos[j]).squaredNorm() < r * r)
              pairs.emplace_back(j, static_cast<std::uint32_t>(e));
          }
        }
  }
  L.spar_start.assign(n + 1, 0);
  for (const auto& p : pairs) ++L.spar_start[p.first + 1];
  for (std::size_t i = 0; i < n; ++i) L.spar_start[i + 1] += L.spar_start[i];
  L.spar.resize(pairs.size());
  static thread_local std::vector<std::uint32_t> fill;
  fill.assign(L.spar_start.begin(), L.spar_start.end() - 1);
  for (const auto& p : pairs) L.spar[fill[p.first]++] = p.second;
}

}  // namespace

// Runs scan_rows(lo, hi, pairs, walls) over the rows [0, n) in one run of consecutive rows a
// thread: the first thread's rows go straight into the list, the others' into
// world.list_parts, then copied in at their offsets (their row ends, counted from their own
// part, shifted likewise). scan_rows writes row ends into L.start / L.wall_start.
template <int D, typename ScanRows>
void scan_rows_in_parts(World<D>& world, std::size_t n, ScanRows&& scan_rows) {
  auto& L = world.nlist;
  auto& parts = world.list_parts;
  if (parts.size() < static_cast<std::size_t>(world.threads))
    parts.resize(static_cast<std::size_t>(world.threads));
  std::size_t team = 1;
  // Per part, where its pairs and walls end (then begin, once summed); reached by pointer in
  // the region, where the thread-local's name would be each thread's own.
  static thread_local std::vector<std::array<std::size_t, 2>> part_ends;
  part_ends.assign(static_cast<std::size_t>(world.threads) + 1, {0, 0});
  auto* ends = part_ends.data();
  auto* part = parts.data();
#pragma omp parallel num_threads(world.threads)
  {
    std::size_t t = 0;
#ifdef _OPENMP
    t = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    team = static_cast<std::size_t>(omp_get_num_threads());
#endif
    const std::size_t lo = n * t / team, hi = n * (t + 1) / team;
    auto& pairs = t == 0 ? L.other : part[t].other;
    auto& walls = t == 0 ? L.wall : part[t].wall;
    pairs.clear();
    walls.clear();
    scan_rows(lo, hi, pairs, walls);
    ends[t + 1] = {pairs.size(), walls.size()};
  }
  for (std::size_t t = 0; t < team; ++t)
    for (int k = 0; k < 2; ++k) ends[t + 1][k] += ends[t][k];
  resize_with_room(L.other, ends[team][0]);
  resize_with_room(L.wall, ends[team][1]);
  std::uint32_t* other = L.other.data();
  std::uint32_t* wall = L.wall.data();
  for_each_index(static_cast<std::ptrdiff_t>(team), world.threads, true, [&](std::ptrdiff_t tt) {
    const auto t = static_cast<std::size_t>(tt);
    if (t == 0) return;
    std::copy(part[t].other.begin(), part[t].other.end(), other + ends[t][0]);
    std::copy(part[t].wall.begin(), part[t].wall.end(), wall + ends[t][1]);
    const auto pair_base = static_cast<std::uint32_t>(ends[t][0]);
    const auto wall_base = static_cast<std::uint32_t>(ends[t][1]);
    for (std::size_t i = n * t / team; i < n * (t + 1) / team; ++i) {
      L.start[i + 1] += pair_base;
      L.wall_start[i + 1] += wall_base;
    }
  });
}

template <int D>
double skin_length(const World<D>& world) {
  const auto& r = world.particles.radius;
  if (world.domain) return world.domain->skin();
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (double v : r) sum += v;
  return world.skin_factor * sum / static_cast<double>(r.size());
}

template <int D>
void build_neighbour_list(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t n = P.size();
  L.skin = skin_length(world);

  // Peak memory: a build holds the old rows (their history) and the new ones. The crossing
  // scratch goes first, and with what the step gave back (world/step.cpp) leaves even holes of
  // the heap (48 bytes a grain off a settled bed's peak), unless the scratch is small and kept.
  // The old rows (pairs with a history) are a copy; the new rows overwrite the list's arrays.
  if (!world.keep_build_scratch) {
    world.slab_crossing.release();
    give_free_heap_back();
  }
  NeighbourList<D>& old = world.old_rows;
  const std::size_t listed_before = L.other.size();
  keep_loaded_pairs(L, old, n, world.threads);
  const bool have_old = old.start.size() == n + 1;

  auto reset_rows = [&] {
    L.start.assign(n + 1, 0);
    L.other.clear();
    // Room for about as many pairs as before: appending then never doubles the array.
    L.other.reserve(listed_before + listed_before / 8 + 16);
    L.spring.clear();
    L.wall_start.assign(n + 1, 0);
    L.wall.clear();
    L.wall_spring.clear();
    L.extra.clear();
    L.wall_extra.clear();
    L.image.clear();
    L.spar_start.assign(world.spars.empty() ? 0 : n + 1, 0);
    L.spar.clear();
    L.spar_spring.clear();
  };
  reset_rows();

  // (a decomposed cell's ranks search together: their reach is a reduction)
  if (world.cell.periodic && (n > 0 || world.domain)) {
    wrap_into_cell(world);
    if (world.sort_interval > 0 &&
        L.builds % static_cast<std::uint64_t>(world.sort_interval) == 0) {
      // The old rows' images are not carried: the history merges by partner index, and a
      // pair has one image within reach (the cell is at least three reaches across).
      renumber(world, old, L, have_old, periodic_spatial_order(world));
      reset_rows();
    }
    list_periodic_pairs(world);
  } else if (n > 0) {
    // Grid bounds: the grains' bounding box; far outliers are clamped to the edge cells.
    Vec lo = P.pos[0], hi = P.pos[0];
    double rmax = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      lo = lo.cwiseMin(P.pos[i]);
      hi = hi.cwiseMax(P.pos[i]);
      rmax = std::max(rmax, P.radius[i]);
    }
    double cell = 2.0 * rmax + L.skin;
    // Bound the number of cells to a few per grain, whatever the spread.
    const double max_cells = 4.0 * static_cast<double>(n) + 64.0;
    for (;;) {
      double cells = 1.0;
      for (int k = 0; k < D; ++k) cells *= std::floor((hi[k] - lo[k]) / cell) + 1.0;
      if (cells <= max_cells) break;
      cell *= 1.25;
    }
    // Kept between builds, one per calling thread (a study's runs are threads). Parallel
    // regions reach it through `g`: by its own name each OpenMP thread would see its own.
    static thread_local Grid<D> grid;
    Grid<D>& g = grid;
    g.lo = lo;
    g.inv_cell = 1.0 / cell;
    for (int k = 0; k < D; ++k)
      g.dims[k] = static_cast<int>(std::floor((hi[k] - lo[k]) / cell)) + 1;
    const std::size_t ncells = static_cast<std::size_t>(g.dims[0]) * g.dims[1] * g.dims[2];
    g.cell_start.assign(ncells + 1, 0);
    g.cell_of.resize(n);
    g.sorted.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::array<int, 3> c{0, 0, 0};
      for (int k = 0; k < D; ++k) c[k] = g.coord(P.pos[i], k);
      g.cell_of[i] = g.cell_index(c);
      ++g.cell_start[g.cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < ncells; ++c) g.cell_start[c + 1] += g.cell_start[c];
    {
      static thread_local std::vector<std::uint32_t> fill;
      fill.assign(g.cell_start.begin(), g.cell_start.end() - 1);
      for (std::size_t i = 0; i < n; ++i)
        g.sorted[fill[g.cell_of[i]]++] = static_cast<std::uint32_t>(i);
    }
    if (world.sort_interval > 0 &&
        L.builds % static_cast<std::uint64_t>(world.sort_interval) == 0) {
      renumber(world, old, L, have_old, g.sorted);
      reset_rows();
      // Grains are now in cell order: the sort is the identity.
      for (std::size_t k = 0; k < n; ++k) {
        g.sorted[k] = static_cast<std::uint32_t>(k);
      }
      std::vector<std::uint32_t> cells(n);
      for (std::size_t c = 0; c < ncells; ++c)
        for (std::uint32_t k = g.cell_start[c]; k < g.cell_start[c + 1]; ++k)
          cells[k] = static_cast<std::uint32_t>(c);
      g.cell_of.swap(cells);
    }

    // Rows in two passes over the grains, each on several threads: count every row's
    // pairs, then fill each row at its offset. The rows are the same whatever the threads.
    const int zr = D == 3 ? 1 : 0;
    const bool clumps = !P.clump.empty();
    // Calls pair(j) for each grain j > i within reach of grain i, and wall(w) for each
    // wall within reach.
    // A ghost (domain/slab_domain.hpp) pairs with the rank's own grains only, and has no walls.
    const std::uint8_t* flags = P.flags.data();
    auto scan = [&](std::size_t i, auto&& pair, auto&& wall) {
      const Vec xi = P.pos[i];
      const bool ghost = flags[i] & kGhost;
      const std::uint32_t ci = clumps ? P.clump[i] : kNoClump;
      const double ri = P.radius[i] + L.skin;
      std::array<int, 3> c{0, 0, 0};
      for (int k = 0; k < D; ++k) c[k] = g.coord(xi, k);
      for (int dz = -zr; dz <= zr; ++dz) {
        const int cz = c[2] + dz;
        if (cz < 0 || cz >= g.dims[2]) continue;
        for (int dy = -1; dy <= 1; ++dy) {
          const int cy = c[1] + dy;
          if (cy < 0 || cy >= g.dims[1]) continue;
          const int cx0 = std::max(c[0] - 1, 0), cx1 = std::min(c[0] + 1, g.dims[0] - 1);
          // Cells cx0..cx1 of one row are contiguous in the sorted array.
          const std::uint32_t b = g.cell_start[g.cell_index({cx0, cy, cz})];
          const std::uint32_t e = g.cell_start[g.cell_index({cx1, cy, cz}) + 1];
          for (std::uint32_t s = b; s < e; ++s) {
            const std::uint32_t j = g.sorted[s];
            if (j <= i) continue;
            if (ci != kNoClump && P.clump[j] == ci) continue;  // members of one clump
            if (ghost && (flags[j] & kGhost)) continue;
            const double reach = ri + P.radius[j];
            if ((P.pos[j] - xi).squaredNorm() < reach * reach) pair(j);
          }
        }
      }
      // Walls: few, so every grain checks each (documented in docs/architecture.md).
      for (std::size_t w = 0; w < world.walls.size() && !ghost; ++w) {
        Vec q;
        wall_closest(world.walls[w], xi, q, /*apply_owner_rule=*/false);
        const auto& wl = world.walls[w];
        const double gap =
            wl.kind == WallKind::kPlane ? (xi - wl.point).dot(wl.normal) : (q - xi).norm();
        if (gap < ri) wall(static_cast<std::uint32_t>(w));
      }
    };
    // One pass over the rows. With several threads each takes a run of consecutive rows: the
    // first appends its rows to the list itself, the others to parts of their own, copied in
    // after it (a count pass and a fill pass scanned every grain's cells twice). The rows are
    // the same whatever the threads.
    auto scan_rows = [&](std::size_t first, std::size_t last, std::vector<std::uint32_t>& pairs,
                         std::vector<std::uint32_t>& walls) {
      for (std::size_t i = first; i < last; ++i) {
        const std::size_t row_begin = pairs.size();
        scan(
            i, [&](std::uint32_t j) { pairs.push_back(j); },
            [&](std::uint32_t w) { walls.push_back(w); });
        std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(row_begin), pairs.end());
        L.start[i + 1] = static_cast<std::uint32_t>(pairs.size());
        L.wall_start[i + 1] = static_cast<std::uint32_t>(walls.size());
      }
    };
    if (world.threads > 1 && n >= kParallelMin)
      scan_rows_in_parts(world, n, scan_rows);
    else
      scan_rows(0, n, L.other, L.wall);
    if (!world.spars.empty()) list_spar_pairs(world, g, rmax);
  }

  resize_with_room(L.spring, L.other.size());
  resize_with_room(L.wall_spring, L.wall.size());
  const bool extras = world.contact_extras;
  const bool old_extras =
      have_old && old.extra.size() == old.other.size() && old.wall_extra.size() == old.wall.size();
  if (extras) {
    resize_with_room(L.extra, L.other.size());
    resize_with_room(L.wall_extra, L.wall.size());
  }
  const ContactExtra<D> no_extra{};
  // A bonded pair that is no longer listed has separated beyond the skin: its bond is
  // broken (only possible when a bond's elastic stretch exceeds the skin).
  auto drop_nothing = [](const auto&) {};
  std::uint64_t dropped_bonds = 0;  // a count: the same in any order
  const auto rows = static_cast<std::ptrdiff_t>(n);
  // Row i's history merged; the bonds it drops counted in `dropped`.
  auto merge_row = [&](std::ptrdiff_t ii, std::uint64_t& dropped) {
    const auto i = static_cast<std::size_t>(ii);
    auto drop_extra = [&dropped](const ContactExtra<D>& e) { dropped += e.bonded; };
    const std::size_t nb = L.start[i], nn = L.start[i + 1] - nb;
    const std::size_t wb = L.wall_start[i], wn = L.wall_start[i + 1] - wb;
    if (have_old) {
      const std::size_t ob = old.start[i], on = old.start[i + 1] - ob;
      merge_history(old.other.data() + ob, old.spring.data() + ob, on, L.other.data() + nb,
                    L.spring.data() + nb, nn, unloaded_spring<D>(), drop_nothing);
      const std::size_t owb = old.wall_start[i], own = old.wall_start[i + 1] - owb;
      merge_history(old.wall.data() + owb, old.wall_spring.data() + owb, own, L.wall.data() + wb,
                    L.wall_spring.data() + wb, wn, unloaded_spring<D>(), drop_nothing);
      if (extras && old_extras) {
        merge_history(old.other.data() + ob, old.extra.data() + ob, on, L.other.data() + nb,
                      L.extra.data() + nb, nn, no_extra, drop_extra);
        merge_history(old.wall.data() + owb, old.wall_extra.data() + owb, own, L.wall.data() + wb,
                      L.wall_extra.data() + wb, wn, no_extra, drop_nothing);
      }
    } else {
      for (std::size_t k = 0; k < nn; ++k) L.spring[nb + k] = unloaded_spring<D>();
      for (std::size_t k = 0; k < wn; ++k) L.wall_spring[wb + k] = unloaded_spring<D>();
    }
  };
  if (world.threads > 1 && n >= kParallelMin) {  // (else no region: base/parallel.hpp)
#pragma omp parallel for num_threads(world.threads) schedule(static) reduction(+ : dropped_bonds)
    for (std::ptrdiff_t ii = 0; ii < rows; ++ii) merge_row(ii, dropped_bonds);
  } else {
    for (std::ptrdiff_t ii = 0; ii < rows; ++ii) merge_row(ii, dropped_bonds);
  }
  world.broken_bonds += dropped_bonds;
  if (!L.spar_start.empty()) {
    L.spar_spring.assign(L.spar.size(), unloaded_spring<D>());
    if (have_old && old.spar_start.size() == n + 1) {
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t sb = L.spar_start[i], sn = L.spar_start[i + 1] - sb;
        const std::size_t ob = old.spar_start[i], on = old.spar_start[i + 1] - ob;
        merge_history(old.spar.data() + ob, old.spar_spring.data() + ob, on, L.spar.data() + sb,
                      L.spar_spring.data() + sb, sn, unloaded_spring<D>(), drop_nothing);
      }
    }
  }

  // The old rows' arrays, the other threads' parts of the rows and the force arrays (given
  // back for the build) would be mapped afresh at the next build and step: page faults that
  // cost a small system about a tenth of its run (docs/performance.md, "Threads"). Below
  // kSmallBuildScratch all three stay mapped; above it the peak memory per grain rules and
  // they go back to the system.
  std::size_t scratch =
      old.bytes() + n * (sizeof(typename Dim<D>::Vec) + sizeof(typename Dim<D>::Rot));
  for (const auto& part : world.list_parts)
    scratch += (part.other.capacity() + part.wall.capacity()) * sizeof(std::uint32_t);
  world.keep_build_scratch = scratch < kSmallBuildScratch;
  if (!world.keep_build_scratch) {
    old = NeighbourList<D>{};
    world.list_parts.clear();
    world.list_parts.shrink_to_fit();
  }

  P.pos_at_build = P.pos;
  world.cell.h_at_build = world.cell.h;
  for (auto& w : world.walls) w.displacement = Vec::Zero();
  world.spars.pos_at_build = world.spars.pos;
  world.disp_bound = 0.0;
  world.radius_growth = 0.0;
  world.rebuild_needed = false;
  ++L.builds;
}

template void build_neighbour_list<2>(World<2>&);
template void build_neighbour_list<3>(World<3>&);
template double skin_length<2>(const World<2>&);
template double skin_length<3>(const World<3>&);

}  // namespace geodem
