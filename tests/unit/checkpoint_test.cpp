// Checkpoints (io/checkpoint.hpp, world/world_state.hpp): a world saved and loaded into a
// fresh one built from the same settings continues bit for bit like the original; files
// that are corrupt or cut short are detected by their length and checksum, and the
// newest valid file is used instead.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "controllers/radius_growth.hpp"
#include "controllers/stress_servo.hpp"
#include "io/checkpoint.hpp"
#include "pressed_packing.hpp"
#include "world/world_state.hpp"

namespace geodem::test {
namespace {

namespace fs = std::filesystem;

template <typename T>
class WorldCheckpoint : public ::testing::Test {};
TYPED_TEST_SUITE(WorldCheckpoint, Dims, DimNames);

// Everything here comes from the "scenario": the part a resumed run rebuilds before loading
// the checkpoint.
template <int D>
World<D> make_world(bool extras) {
  return pressed_packing<D>(extras, 1500, D == 2 ? 30 : 8, 20.0, 5);
}

template <int D>
void advance(World<D>& w, int from, int to) {
  for (int k = from; k < to; ++k) {
    if (k == 60) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor starts sliding
    w.measure_this_step = k % 25 == 0;
    step(w);
  }
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TYPED_TEST(WorldCheckpoint, ResumedWorldContinuesBitForBit) {
  constexpr int D = TypeParam::value;
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    World<D> a = make_world<D>(extras);
    advance(a, 0, 150);
    StateWriter saved;
    save_world_state(saved, a);

    World<D> b = make_world<D>(extras);  // rebuilt from the settings, then loaded
    StateReader in(saved.bytes().data(), saved.bytes().size());
    load_world_state(in, b);
    EXPECT_TRUE(in.at_end());
    advance(a, 150, 300);
    advance(b, 150, 300);

    EXPECT_GT(a.nlist.builds, 3u);
    if (extras) {
      EXPECT_GT(a.broken_bonds, 0u);
    }
    EXPECT_TRUE(same_bits(a.particles.pos, b.particles.pos));
    EXPECT_TRUE(same_bits(a.particles.vel, b.particles.vel));
    EXPECT_TRUE(same_bits(a.particles.angvel, b.particles.angvel));
    EXPECT_TRUE(same_bits(a.particles.id, b.particles.id));
    EXPECT_TRUE(same_bits(a.nlist.spring, b.nlist.spring));
    ASSERT_EQ(a.nlist.extra.size(), b.nlist.extra.size());
    for (std::size_t k = 0; k < a.nlist.extra.size(); ++k) {  // field by field: padding aside
      const auto &ea = a.nlist.extra[k], &eb = b.nlist.extra[k];
      ASSERT_TRUE(ea.roll == eb.roll && ea.twist == eb.twist && ea.bonded == eb.bonded) << k;
    }
    for (std::size_t k = 0; k < a.walls.size(); ++k)
      EXPECT_TRUE(a.walls[k].force == b.walls[k].force) << "wall " << k;
    EXPECT_EQ(a.broken_bonds, b.broken_bonds);
    EXPECT_EQ(a.dt, b.dt);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.step, b.step);
    EXPECT_EQ(kinetic_energy(a), kinetic_energy(b));
  }
}

// Controllers travel with the world's state: a world loaded with them continues bit for bit.
TYPED_TEST(WorldCheckpoint, ControllersTravelWithTheWorld) {
  constexpr int D = TypeParam::value;
  auto controlled = [](World<D> w) {
    LabBox<D> box;  // add_box's walls: lo0, hi0, lo1, hi1 (, lo2, hi2)
    for (int k = 0; k < D; ++k) box.lo[k] = 2 * k, box.hi[k] = 2 * k + 1;
    w.controllers.push_back(std::make_shared<StressServo<D>>(box, 0, 1.0, 0.5));
    w.controllers.push_back(std::make_shared<RadiusGrowth<D>>(box, 1.0, 1.001, 1.0001));
    return w;
  };
  World<D> a = controlled(make_world<D>(false));
  advance(a, 0, 150);
  StateWriter saved;
  save_world_state(saved, a);
  World<D> b = controlled(make_world<D>(false));
  StateReader in(saved.bytes().data(), saved.bytes().size());
  load_world_state(in, b);
  EXPECT_TRUE(in.at_end());
  advance(a, 150, 300);
  advance(b, 150, 300);
  EXPECT_TRUE(same_bits(a.particles.pos, b.particles.pos));
  EXPECT_TRUE(a.walls[1].point == b.walls[1].point);
  for (std::size_t k = 0; k < a.controllers.size(); ++k) {
    StateWriter sa, sb;
    a.controllers[k]->save_state(sa);
    b.controllers[k]->save_state(sb);
    EXPECT_EQ(sa.bytes(), sb.bytes()) << "controller " << k;
  }
}

// The servo's integral term and the radius growth's switch are restored: a loaded servo
// drives its walls as the original does, one started afresh does not.
TEST(ControllerState, ServoAndGrowthResumeWhereTheyWere) {
  World<2> w;
  w.materials = {linear_material(1e6, 5e5, 0.5, 0.3, 2600.0)};
  const LabBox<2> box = LabBox<2>::add_to(w, Vec<2>(0.0, 0.0), Vec<2>(1.0, 1.0), 0);
  w.dt = 1.0;
  // 2000 Pa on the faces normal to x (area 1 m per m), against a target of 1000 Pa.
  for (auto k : {box.lo[0], box.hi[0]}) {
    w.walls[k].stiffness = 1e6;
    w.walls[k].force = -2000.0 * w.walls[k].normal;
  }
  StressServo<2> servo(box, 0, 1000.0, 0.5);
  RadiusGrowth<2> growth(box, 500.0, 1.01, 1.001, 1);
  for (int k = 0; k < 5; ++k) servo.apply(w), growth.apply(w);
  ASSERT_TRUE(growth.reached());
  StateWriter out;
  servo.save_state(out);
  growth.save_state(out);
  StressServo<2> loaded(box, 0, 1000.0, 0.5), fresh(box, 0, 1000.0, 0.5);
  RadiusGrowth<2> loaded_growth(box, 500.0, 1.01, 1.001, 1);
  StateReader in(out.bytes().data(), out.bytes().size());
  loaded.load_state(in);
  loaded_growth.load_state(in);
  EXPECT_TRUE(in.at_end());
  EXPECT_TRUE(loaded_growth.reached());
  World<2> wa = w, wb = w, wf = w;
  servo.apply(wa), loaded.apply(wb), fresh.apply(wf);
  EXPECT_TRUE(wa.walls[box.hi[0]].velocity == wb.walls[box.hi[0]].velocity);
  EXPECT_FALSE(wa.walls[box.hi[0]].velocity == wf.walls[box.hi[0]].velocity);
}

TYPED_TEST(WorldCheckpoint, RefusesAnotherScenariosWorld) {
  constexpr int D = TypeParam::value;
  World<D> a = make_world<D>(false);
  StateWriter saved;
  save_world_state(saved, a);
  World<D> b = make_world<D>(false);
  b.walls.pop_back();  // another scenario: one wall fewer
  StateReader in(saved.bytes().data(), saved.bytes().size());
  EXPECT_THROW(load_world_state(in, b), CheckpointError);
}

TEST(StateArchive, RoundTripAndTruncation) {
  StateWriter w;
  const std::vector<double> v = {1.5, -2.0, 3.25};
  const Eigen::Vector3d x(1, 2, 3);
  w(std::uint32_t{7}), w(v), w(std::string("walls")), w(x);
  std::uint32_t a = 0;
  std::vector<double> v2;
  std::string s;
  Eigen::Vector3d x2;
  StateReader r(w.bytes().data(), w.bytes().size());
  r(a), r(v2), r(s), r(x2);
  EXPECT_EQ(a, 7u);
  EXPECT_EQ(v2, v);
  EXPECT_EQ(s, "walls");
  EXPECT_EQ(x2, x);
  EXPECT_TRUE(r.at_end());
  // Every cut of the bytes is detected, never read beyond.
  for (std::size_t cut = 0; cut < w.bytes().size(); ++cut) {
    StateReader t(w.bytes().data(), cut);
    EXPECT_THROW((t(a), t(v2), t(s), t(x2)), CheckpointError) << "cut at " << cut;
  }
  // A length field far beyond the data does not allocate it.
  StateWriter huge;
  huge(std::uint64_t{1} << 60);
  StateReader h(huge.bytes().data(), huge.bytes().size());
  EXPECT_THROW(h(v2), CheckpointError);
}

class CheckpointFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::unique_temp_dir("checkpoint");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  Checkpoint make(std::uint64_t step) {
    Checkpoint c;
    c.kind = "scene";
    c.dimension = 2;
    c.step = step;
    c.time = 1e-3 * static_cast<double>(step);
    c.scenario = "{\"seed\": 1}";
    c.runner = "runner state";
    c.world = std::string(1000, static_cast<char>(step));
    return c;
  }
  std::string dir() const { return dir_.string(); }
  fs::path dir_;
};

TEST_F(CheckpointFiles, KeepsTheNewestAndReadsThemBack) {
  for (std::uint64_t s : {100, 200, 300}) write_checkpoint(dir(), make(s), 2);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(checkpoint_folder(dir())))
    files += e.is_regular_file();
  EXPECT_EQ(files, 2u);  // the oldest pruned, no temporary file left
  const Checkpoint c = load_latest_checkpoint(dir(), nullptr);
  EXPECT_EQ(c.step, 300u);
  EXPECT_EQ(c.world, make(300).world);
  EXPECT_EQ(c.scenario, make(300).scenario);
}

TEST_F(CheckpointFiles, StreamedWorldGivesTheSameFile) {
  // The world archived field by field straight into the file (counted, then streamed,
  // the checksum patched in the header) against the same bytes given whole.
  std::vector<double> pos = {1.0, -2.5, 3.25};
  std::vector<std::uint32_t> ids = {7, 8, 9};
  StateWriter whole;
  whole(pos), whole(ids), whole(std::string("walls"));
  Checkpoint c = make(400);
  c.world = whole.bytes();
  const std::string a = dir() + "/whole.bin", b = dir() + "/streamed.bin";
  write_checkpoint_file(a, c);
  write_checkpoint_file(b, c, [&](StateWriter& w) { w(pos), w(ids), w(std::string("walls")); });
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(fa)), {});
  const std::string bytes_b((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_EQ(bytes_a, bytes_b);
  EXPECT_EQ(read_checkpoint(b).world, c.world);
  // A world that archives differently in its two passes is a programming error.
  int pass = 0;
  EXPECT_THROW(write_checkpoint_file(dir() + "/bad.bin", c,
                                     [&](StateWriter& w) { w(std::vector<int>(++pass, 0)); }),
               std::logic_error);
}

TEST_F(CheckpointFiles, CorruptOrTruncatedNewestFallsBackToThePrevious) {
  write_checkpoint(dir(), make(100), 3);
  const std::string newest = write_checkpoint(dir(), make(200), 3);
  const auto size = fs::file_size(newest);
  {  // one byte flipped in the middle of the state
    std::fstream f(newest, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
  }
  std::vector<std::string> skipped;
  EXPECT_EQ(load_latest_checkpoint(dir(), &skipped).step, 100u);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("checksum"), std::string::npos) << skipped[0];

  write_checkpoint(dir(), make(300), 3);
  fs::resize_file(checkpoint_folder(dir()) + "/checkpoint_000000000300.bin", size - 10);
  skipped.clear();
  EXPECT_EQ(load_latest_checkpoint(dir(), &skipped).step, 100u);
  ASSERT_EQ(skipped.size(), 2u);
  EXPECT_NE(skipped[0].find("truncated"), std::string::npos) << skipped[0];

  fs::resize_file(checkpoint_folder(dir()) + "/checkpoint_000000000100.bin", 5);
  EXPECT_THROW(load_latest_checkpoint(dir(), nullptr), CheckpointError);
}

TEST_F(CheckpointFiles, NoCheckpointIsAnError) {
  EXPECT_THROW(load_latest_checkpoint(dir(), nullptr), CheckpointError);
  std::ofstream(checkpoint_folder(dir()) + "_not_a_folder") << "x";
  fs::create_directories(checkpoint_folder(dir()));
  std::ofstream(checkpoint_folder(dir()) + "/checkpoint_000000000001.bin") << "not a checkpoint";
  EXPECT_THROW(read_checkpoint(checkpoint_folder(dir()) + "/checkpoint_000000000001.bin"),
               CheckpointError);
}

}  // namespace
}  // namespace geodem::test
