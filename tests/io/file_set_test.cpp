// A file set replaced as one: the whole old set or the whole new one after any failure, no link
// written through, only the set's own earlier members removed.
#include "slicecap/io/file_set.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <map>

#include "../support/file_size_limit.hpp"
#include "../support/small_disk.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Every file in a folder (recursively, hidden ones too) with its contents.
std::map<std::string, std::string> snapshot(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    files[fs::relative(entry.path(), folder).string()] =
        entry.is_symlink() ? "-> " + fs::read_symlink(entry.path()).string()
        : entry.is_regular_file() ? contents(entry.path())
                                  : "<folder>";
  return files;
}

FileSetEntry text(const std::string& name, const std::string& body) {
  return {name, [body](const fs::path& path) {
            std::ofstream out(path, std::ios::binary);
            out << body;
            out.close();
            if (!out) throw IoError(path.string() + ": write failed");
          }};
}

TEST(FileSet, ReplacesItsOwnMembersOnlyAndListsThemInAManifest) {
  const auto folder = test::freshTempDir() / "out";
  fs::create_directories(folder);
  std::ofstream(folder / "s-abrdf-mine.exr") << "not written by the set";
  std::ofstream(folder / "notes.txt") << "the person's own file";
  const auto first = replaceFileSet(
      folder, "s", {text("s-abrdf-b.exr", "b1"), text("s-abrdf-a.exr", "a1"), text("s.csv", "c1")});
  EXPECT_EQ(first, (std::vector<fs::path>{folder / "s-abrdf-b.exr", folder / "s-abrdf-a.exr",
                                          folder / "s.csv"}));
  EXPECT_EQ(fileSetMembers(folder, "s"),
            (std::vector<std::string>{"s-abrdf-b.exr", "s-abrdf-a.exr", "s.csv"}));
  replaceFileSet(folder, "s", {text("s-abrdf-b.exr", "b2"), text("s.csv", "c2")});
  EXPECT_EQ(contents(folder / "s-abrdf-b.exr"), "b2");
  EXPECT_EQ(contents(folder / "s.csv"), "c2");
  EXPECT_FALSE(fs::exists(folder / "s-abrdf-a.exr")) << "the set's own stale member goes";
  EXPECT_EQ(contents(folder / "s-abrdf-mine.exr"), "not written by the set");
  EXPECT_EQ(contents(folder / "notes.txt"), "the person's own file");
  EXPECT_FALSE(fs::exists(folder / ".s-export.partial")) << "no staging folder is left";
  // A member kept (not made this time) stays, and stays listed.
  replaceFileSet(folder, "s", {text("s.csv", "c3")}, {"s-abrdf-b.exr"});
  EXPECT_EQ(contents(folder / "s-abrdf-b.exr"), "b2");
  EXPECT_EQ(fileSetMembers(folder, "s"), (std::vector<std::string>{"s.csv", "s-abrdf-b.exr"}));
}

TEST(FileSet, APlantedLinkIsReplacedNeverWrittenThrough) {
  const auto dir = test::freshTempDir();
  const auto folder = dir / "out";
  fs::create_directories(folder);
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", folder / "s-summary.json");
  fs::create_symlink(dir / "victim", folder / "s-manifest.json");
  fs::create_directory_symlink(dir, folder / ".s-export.partial");
  replaceFileSet(folder, "s", {text("s-summary.json", "{}")});
  EXPECT_EQ(contents(dir / "victim"), "precious");
  EXPECT_FALSE(fs::is_symlink(folder / "s-summary.json"));
  EXPECT_EQ(contents(folder / "s-summary.json"), "{}");
  EXPECT_FALSE(fs::is_symlink(folder / "s-manifest.json"));
  EXPECT_TRUE(fs::exists(dir / "victim")) << "nothing the link named was removed";
}

TEST(FileSet, AFailedWriteLeavesTheOldSetWhole) {
  const auto folder = test::freshTempDir() / "out";
  replaceFileSet(folder, "s", {text("s-a", "old a"), text("s-b", std::string(1000, 'b'))});
  const auto before = snapshot(folder);
  {
    // Like a full disk: the second file cannot be written whole.
    test::FileSizeLimit limit(500);
    try {
      replaceFileSet(folder, "s", {text("s-a", "new a"), text("s-b", std::string(1000, 'B'))});
      ADD_FAILURE() << "no error";
    } catch (const IoError& error) {
      EXPECT_NE(std::string(error.what()).find("s-b"), std::string::npos) << error.what();
      EXPECT_EQ(std::string(error.what()).find("/proc/"), std::string::npos) << error.what();
    }
  }
  EXPECT_EQ(snapshot(folder), before);
  // A writer that throws anything else: the same, and its exception passes through.
  EXPECT_THROW(replaceFileSet(folder, "s",
                              {text("s-a", "new a"),
                               {"s-b", [](const fs::path&) { throw std::runtime_error("no"); }}}),
               std::runtime_error);
  EXPECT_EQ(snapshot(folder), before);
  EXPECT_THROW(replaceFileSet(folder, "s", {text("../s-a", "x")}), io::IoError);
  EXPECT_THROW(replaceFileSet(folder, "s", {text("s-a", "x"), text("s-a", "y")}),
               io::IoError);
}

TEST(FileSet, AFullDiskLeavesTheOldSetWhole) {
  const auto dir = test::freshTempDir() / "small";
  test::SmallDisk disk(dir, "1M");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a small tmpfs here (" << disk.why() << ")";
  const auto folder = dir / "out";
  replaceFileSet(folder, "s",
                 {text("s-a", std::string(100000, 'a')), text("s-b", std::string(100000, 'b'))});
  const auto before = snapshot(folder);
  disk.fill(dir / "filler", 150000);
  EXPECT_THROW(replaceFileSet(folder, "s",
                              {text("s-a", std::string(100000, 'A')),
                               text("s-b", std::string(100000, 'B'))}),
               IoError);
  EXPECT_EQ(snapshot(folder), before);
  // Once there is room again the new set goes in whole.
  fs::remove(dir / "filler");
  replaceFileSet(folder, "s",
                 {text("s-a", std::string(100000, 'A')), text("s-b", std::string(100000, 'B'))});
  EXPECT_EQ(contents(folder / "s-b"), std::string(100000, 'B'));
}

}  // namespace
}  // namespace slicecap::io
