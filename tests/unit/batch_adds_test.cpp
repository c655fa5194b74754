// The branch-free add pass (contacts/batch_adds.hpp) gives every grain the same bits as the
// scalar loop it replaces: forces and torques added to partner j in list order, each row's own
// sums (0 - f - f ..., in order) added to grain i when the row closes, partners beyond the slab
// handed to its crossings in list order. The contacts are built by hand: rows of 1 to 7
// contacts, rows that span two or three batches, batches of one contact, partners in the next
// slab, a grain that is a partner of several rows before its own, values of mixed magnitudes
// and signed zeros, and force arrays that start from -0 and from other values.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "contacts/batch_adds.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class BatchAdds : public ::testing::Test {};
TYPED_TEST_SUITE(BatchAdds, Dims, DimNames);

template <int D>
struct HandContact {
  std::size_t i, j;
  double f[D], tqi[ContactBatch<D>::kRot], tj[ContactBatch<D>::kRot];
};

double awkward_value(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  switch (kind(rng)) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return u(rng) * 1e12;
    case 3:
      return u(rng) * 1e-12;
    default:
      return u(rng);
  }
}

TYPED_TEST(BatchAdds, SameBitsAsTheScalarLoop) {
  constexpr int D = TypeParam::value;
  constexpr int kRot = ContactBatch<D>::kRot;
  constexpr std::size_t n = 300, last = 200;  // slab 0 is [0, 200), slab 1 [200, 300)
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> row_len(0, 7), batch_len(1, ContactBatch<D>::kSize);
  std::vector<HandContact<D>> contacts;
  for (std::size_t i = 0; i < last; ++i) {
    // Partners above i (a half list), some in the next slab; rows 40-60 all name grain 61.
    std::vector<std::size_t> js;
    if (i >= 40 && i < 60) js.push_back(61);
    const int len = i % 50 == 7 ? 150 : row_len(rng);  // a few rows longer than two batches
    std::uniform_int_distribution<std::size_t> partner(i + 1, n - 1);
    for (int m = 0; m < len; ++m) js.push_back(partner(rng));
    for (std::size_t j : js) {
      HandContact<D> c{i, j, {}, {}, {}};
      for (double& v : c.f) v = awkward_value(rng);
      for (double& v : c.tqi) v = awkward_value(rng);
      for (double& v : c.tj) v = awkward_value(rng);
      contacts.push_back(c);
    }
  }
  std::vector<double> start_f(n * D), start_t(n * kRot);
  for (std::size_t k = 0; k < start_f.size(); ++k)
    start_f[k] = k % 3 == 0 ? -0.0 : 0.5 * static_cast<double>(k);
  for (std::size_t k = 0; k < start_t.size(); ++k)
    start_t[k] = k % 2 == 0 ? -0.0 : 0.25 * static_cast<double>(k);

  // The scalar loop, as batched_pairs.cpp wrote it before the branch-free pass.
  std::vector<double> ref_f = start_f, ref_t = start_t;
  std::vector<SlabCrossing<D>> ref_cross;
  {
    std::size_t open = last;
    double fi[D] = {}, ti[kRot] = {};
    auto close = [&] {
      if (open == last) return;
      for (int a = 0; a < D; ++a) ref_f[open * D + a] += fi[a], fi[a] = 0.0;
      for (int a = 0; a < kRot; ++a) ref_t[open * kRot + a] += ti[a], ti[a] = 0.0;
      open = last;
    };
    for (const auto& c : contacts) {
      if (c.i != open) {
        close();
        open = c.i;
      }
      for (int a = 0; a < D; ++a) fi[a] -= c.f[a];
      for (int a = 0; a < kRot; ++a) ti[a] -= c.tqi[a];
      if (c.j < last) {
        for (int a = 0; a < D; ++a) ref_f[c.j * D + a] += c.f[a];
        for (int a = 0; a < kRot; ++a) ref_t[c.j * kRot + a] += c.tj[a];
      } else {
        SlabCrossing<D> x;
        for (int a = 0; a < D; ++a) x.a[a] = c.f[a];
        if constexpr (D == 3) {
          for (int a = 0; a < kRot; ++a) x.b[a] = c.tj[a];
        } else {
          x.b = c.tj[0];
        }
        x.body = static_cast<std::uint32_t>(c.j);
        ref_cross.push_back(x);
      }
    }
    close();
  }

  // The branch-free pass, over batches of random lengths (rows cut anywhere).
  const std::vector<std::uint32_t> starts{0, static_cast<std::uint32_t>(last), n};
  SlabCrossings<SlabCrossing<D>> crossings;
  crossings.prepare(SlabPlan::given(n, starts), 1);
  auto writer = crossings.slab(0);
  crossings.slab(1);  // (its buckets emptied)
  std::vector<double> got_f = start_f, got_t = start_t;
  auto batch = std::make_unique<ContactBatch<D>>();
  OpenRowSums<D> open{last};
  int batches = 0, single = 0;
  for (std::size_t next = 0; next < contacts.size();) {
    const int len = batches % 9 == 4 ? 1 : batch_len(rng);
    int m = 0;
    for (; m < len && next < contacts.size(); ++m, ++next) {
      const auto& c = contacts[next];
      batch->i[m] = static_cast<std::int64_t>(c.i);
      batch->j[m] = static_cast<std::int64_t>(c.j);
      for (int a = 0; a < D; ++a) batch->f[a][m] = c.f[a];
      for (int a = 0; a < kRot; ++a) batch->tqi[a][m] = c.tqi[a], batch->tj[a][m] = c.tj[a];
    }
    add_plain_batch<D>(*batch, m, last, got_f.data(), got_t.data(), open, writer);
    ++batches;
    single += m == 1 ? 1 : 0;
  }
  // The slab's end closes the last row (batched_pairs.cpp's close_row).
  ASSERT_NE(open.row, last);
  close_open_row(open, last, got_f.data(), got_t.data());
  ASSERT_EQ(open.row, last);
  EXPECT_GT(batches, 20);
  EXPECT_GT(single, 2);

  ASSERT_EQ(0, std::memcmp(ref_f.data(), got_f.data(), ref_f.size() * sizeof(double)));
  ASSERT_EQ(0, std::memcmp(ref_t.data(), got_t.data(), ref_t.size() * sizeof(double)));
  std::vector<SlabCrossing<D>> got_cross;
  crossings.apply(1, [&](const SlabCrossing<D>& x) { got_cross.push_back(x); });
  ASSERT_EQ(got_cross.size(), ref_cross.size());
  ASSERT_GT(ref_cross.size(), 100u);
  for (std::size_t k = 0; k < ref_cross.size(); ++k) {
    // apply() hands them over target slab by target slab: all of these go to slab 1.
    EXPECT_EQ(got_cross[k].body, ref_cross[k].body) << k;
    EXPECT_EQ(0, std::memcmp(&got_cross[k].a, &ref_cross[k].a, sizeof(ref_cross[k].a))) << k;
    EXPECT_EQ(0, std::memcmp(&got_cross[k].b, &ref_cross[k].b, sizeof(ref_cross[k].b))) << k;
  }
}

}  // namespace
}  // namespace geodem::test
