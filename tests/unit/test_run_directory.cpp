// Run directories, frame numbering and crafted files (issue 21): what a run
// may write, move aside or delete, and what it refuses to read.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "geometry/mesh_io.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"
#include "io/run_directory.hpp"
#include "io/scene.hpp"

using namespace bakesim;
namespace fs = std::filesystem;

namespace {

// A fresh, empty scratch directory per test.
fs::path rd_scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bakesim_rundir_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void rd_touch(const fs::path& file, const std::string& text = "x") {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

std::string rd_slurp(const fs::path& file) { return read_file(file); }

}  // namespace

TEST(FrameNumbers, StemsPadToFiveDigitsAndParseBack) {
  EXPECT_EQ(frame_stem(0), "00000");
  EXPECT_EQ(frame_stem(42), "00042");
  EXPECT_EQ(frame_stem(99999), "99999");
  EXPECT_EQ(frame_stem(123456), "123456");
  EXPECT_EQ(frame_number("00042"), 42);
  EXPECT_EQ(frame_number("123456"), 123456);
  EXPECT_FALSE(frame_number(""));
  EXPECT_FALSE(frame_number("12a"));
  EXPECT_FALSE(frame_number("-1"));
  EXPECT_FALSE(frame_number("99999999999999999999"));  // std::stoi threw "stoi" here
}

// Frames past 99,999: "100000.ckpt" sorts before "99999.ckpt" by name; the
// newest must still be found and kept.
TEST(FrameNumbers, CheckpointsPastFrame99999ListAndPruneByNumber) {
  const fs::path run = rd_scratch("ckpt_order");
  Checkpoint c;
  c.solver = "sph";
  for (int frame : {99998, 99999, 100000, 100001}) {
    c.frame = frame;
    write_checkpoint(run, c, 2);
  }
  const auto list = list_checkpoints(run);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].filename(), "100001.ckpt");
  EXPECT_EQ(list[1].filename(), "100000.ckpt");
  // A checkpoint numbered past the one written is not this run's: left alone, and the new one kept.
  rd_touch(run / "checkpoints" / "200000.ckpt");
  c.frame = 100002;
  write_checkpoint(run, c, 2);
  EXPECT_TRUE(fs::exists(run / "checkpoints" / "200000.ckpt"));
  EXPECT_TRUE(fs::exists(run / "checkpoints" / "100002.ckpt"));
  EXPECT_TRUE(fs::exists(run / "checkpoints" / "100001.ckpt"));
  EXPECT_FALSE(fs::exists(run / "checkpoints" / "100000.ckpt"));
  fs::remove_all(run);
}

TEST(RunDirectory, NamesTheFilesARunWrites) {
  for (const char* ours : {"scene.json", "stats.csv", "stats.units.csv", "log.txt", "particles.pvd", "bakesim-run.json",
                           "frames/00012.ply", "frames/123456.vtu", "checkpoints/00003.ckpt", "meshes/00001.obj",
                           "meshes/gradient_baking.png", "meshes/bakesim_heat.mtl", "render/mesh-00001.png",
                           "render/mesh.mp4", "plots/volume.png", "frames/.00099.ply.tmp4242"})
    EXPECT_TRUE(is_run_file(ours)) << ours;
  for (const char* theirs : {"notes.txt", "frames/my.ply", "frames/00012.txt", "checkpoints/best.ckpt", "other/1.ply",
                             "meshes/bunny.obj", "plots/data.csv", "frames"})
    EXPECT_FALSE(is_run_file(theirs)) << theirs;
}

TEST(RunDirectory, NewRunsCreateOrReuseOnlyTheirOwn) {
  const fs::path root = rd_scratch("claims");
  // A missing directory is created and marked.
  { const RunDirectoryClaim claim = claim_new_run(root / "a", "bread", false); }
  EXPECT_TRUE(fs::is_regular_file(root / "a" / kRunMarkerFile));
  EXPECT_EQ(run_scene_name(root / "a"), "bread");
  // An earlier run of the same scene is moved into previous/; the user's file stays where it is.
  rd_touch(root / "a" / "frames" / "00007.ply");
  rd_touch(root / "a" / "stats.csv", "old");
  rd_touch(root / "a" / "notes.txt", "mine");
  {
    const RunDirectoryClaim claim = claim_new_run(root / "a", "bread", false);
    EXPECT_FALSE(claim.moved_aside.empty());
  }
  EXPECT_TRUE(fs::exists(root / "a" / "previous" / "frames" / "00007.ply"));
  EXPECT_EQ(rd_slurp(root / "a" / "previous" / "stats.csv"), "old");
  EXPECT_FALSE(fs::exists(root / "a" / "frames"));
  EXPECT_EQ(rd_slurp(root / "a" / "notes.txt"), "mine");
  // Another scene's run is refused, with --force moved aside.
  EXPECT_THROW(claim_new_run(root / "a", "cookie", false), InputError);
  { const RunDirectoryClaim claim = claim_new_run(root / "a", "cookie", true); }
  EXPECT_EQ(run_scene_name(root / "a"), "cookie");
  EXPECT_EQ(run_scene_name(root / "a" / "previous"), "bread");
  // A foreign directory: refused; with --force used only where no name clashes.
  rd_touch(root / "user" / "scene.json", "// mine");
  EXPECT_THROW(claim_new_run(root / "user", "bread", false), InputError);
  EXPECT_THROW(claim_new_run(root / "user", "bread", true), InputError);
  EXPECT_EQ(rd_slurp(root / "user" / "scene.json"), "// mine");
  EXPECT_FALSE(fs::exists(root / "user" / kRunLockFile));  // refused before anything is written
  // A user's file inside previous/ is never deleted: the next rerun is refused instead.
  rd_touch(root / "a" / "previous" / "keep.txt", "keep");
  EXPECT_THROW(claim_new_run(root / "a", "cookie", false), InputError);
  EXPECT_EQ(rd_slurp(root / "a" / "previous" / "keep.txt"), "keep");
  fs::remove_all(root);
}

TEST(RunDirectory, OneLockHolderAtATime) {
  const fs::path root = rd_scratch("lock");
  RunDirectoryClaim first = claim_new_run(root / "r", "bread", false);
  EXPECT_EQ(rd_slurp(root / "r" / kRunLockFile), std::to_string(::getpid()) + "\n");
  try {
    claim_existing_run(root / "r");
    ADD_FAILURE() << "a second holder got the lock";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("PID " + std::to_string(::getpid())), std::string::npos) << e.what();
  }
  EXPECT_THROW(claim_new_run(root / "r", "bread", false), InputError);
  first.lock = RunDirectoryLock();  // released
  EXPECT_NO_THROW(claim_existing_run(root / "r"));
  EXPECT_THROW(claim_existing_run(root / "nothing-here"), InputError);
  fs::remove_all(root);
}

TEST(CraftedFiles, NonRegularFilesAreRefusedBeforeReading) {
  const fs::path root = rd_scratch("fifo");
  const fs::path fifo = root / "scene.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(read_file(fifo), InputError);  // opening it would block until a writer came
  EXPECT_THROW(load_scene(fifo.string()), InputError);
  EXPECT_THROW(read_file("/dev/zero"), InputError);  // reading it would never end
  rd_touch(root / "big.json", std::string(2000, ' '));
  EXPECT_THROW(read_file(root / "big.json", 1000), InputError);
  EXPECT_EQ(read_file(root / "big.json", 2000).size(), 2000u);
  fs::remove_all(root);
}

TEST(CraftedFiles, ObjVerticesMustBeFiniteNumbers) {
  const fs::path root = rd_scratch("obj");
  const std::string faces = "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";
  rd_touch(root / "good.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n" + faces);
  EXPECT_EQ(load_mesh((root / "good.obj").string()).vertices.size(), 4u);
  for (const char* bad : {"nan", "inf", "1e999", "x"}) {
    rd_touch(root / "bad.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 ") + bad + " 0\nv 0 0 1\n" + faces);
    try {
      load_mesh((root / "bad.obj").string());  // tinyobjloader alone reads these as 0
      ADD_FAILURE() << "accepted a vertex coordinate " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.obj:3"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(root);
}
