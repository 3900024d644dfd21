// libFuzzer target for the impact-set HDF5 reader (see fuzz/README.md).
//
// The input bytes are written to a temporary file (one per process, see temp_name)
// and read with read_impact_set_h5, which opens files by name like every Ricochet command does.
// Properties checked on every input:
//  1. read_impact_set_h5 either returns a set or throws InputError naming the file; any other
//     exception, crash, leak, hang or sanitizer report is a bug;
//  2. a set it accepts survives its own writer: write_impact_set_h5 then read_impact_set_h5 gives
//     the same set (doubles compared bit for bit);
//  3. nothing is left behind: both temporary files are removed after every input (and at exit).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "fuzz_common.hpp"
#include "impact/impact_set.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_impact_h5", what, detail);
}

const ricochet::fuzz::TempH5Files& temps() {
  static const ricochet::fuzz::TempH5Files files("ricochet-fuzz");
  return files;
}
void remove_temporaries() {
  temps().remove();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(remove_temporaries);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = temps().input;
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) fail("cannot write the temporary file", path);
    if (size > 0 && std::fwrite(data, 1, size, f) != size) fail("cannot write", path);
    std::fclose(f);
  }
  ricochet::ImpactSet set;
  try {
    set = ricochet::read_impact_set_h5(path);
  } catch (const ricochet::InputError& e) {
    std::remove(path.c_str());
    if (e.file() != path) fail("InputError names the wrong file:", e.what());
    return 0;  // refused with a located message: the expected outcome for malformed input
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }

  // Accepted input: the writer must reproduce it exactly.
  struct RemoveAtEnd {  // nothing is left in /dev/shm between inputs (only a crash leaves files)
    ~RemoveAtEnd() { remove_temporaries(); }
  } remove_at_end;
  try {
    const std::string& rt = temps().roundtrip;
    std::remove(rt.c_str());
    ricochet::write_impact_set_h5(set, rt);
    const ricochet::ImpactSet back = ricochet::read_impact_set_h5(rt);
    if (!ricochet::fuzz::same_set(set, back)) fail("round trip changed the set");
    for (const auto& name : set.feature_names()) (void)set.feature(name);
  } catch (const std::exception& e) {
    fail("accepted set fails downstream:", e.what());
  }
  return 0;
}
