// common/provenance: the project's FNV-1a 64 against the published test vectors of the FNV
// reference (Fowler, Noll, Vo), and the record of an input file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/error.hpp"
#include "common/provenance.hpp"

namespace ricochet {
namespace {

std::string hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

TEST(Provenance, Fnv1aMatchesThePublishedVectors) {
  EXPECT_EQ(hex(fnv1a("")), "cbf29ce484222325");  // the offset basis itself
  EXPECT_EQ(hex(fnv1a("a")), "af63dc4c8601ec8c");
  EXPECT_EQ(hex(fnv1a("foobar")), "85944171f73967e8");
  // Continuing from a previous hash is hashing the concatenation.
  EXPECT_EQ(fnv1a("bar", fnv1a("foo")), fnv1a("foobar"));
}

TEST(Provenance, FileRecordHasSizeAndContentHash) {
  const auto path = std::filesystem::temp_directory_path() / "ricochet-provenance-test.txt";
  // Larger than the reader's 64 KiB chunk, so that chunking is exercised.
  std::string text(200000, 'x');
  text += "foobar";
  std::ofstream(path, std::ios::binary) << text;
  const auto p = file_provenance(path.string(), "DATA");
  EXPECT_EQ(p["file"], path.string());
  EXPECT_EQ(p["bytes"].get<std::size_t>(), text.size());
  EXPECT_EQ(p["fnv1a64"], hex(fnv1a(text)));
  std::filesystem::remove(path);
  EXPECT_THROW(file_provenance(path.string(), "DATA"), InputError);
}

}  // namespace
}  // namespace ricochet
