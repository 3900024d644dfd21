#include "common/provenance.hpp"

#include <fmt/format.h>

#include <fstream>
#include <vector>

#include "common/error.hpp"

namespace ricochet {

std::uint64_t fnv1a(std::string_view text, std::uint64_t h) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;  // the 64-bit FNV prime
  }
  return h;
}

nlohmann::json file_provenance(const std::string& path, const std::string& option) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, option, "cannot open the file for reading");
  std::uint64_t h = kFnvOffset;
  std::uint64_t bytes = 0;
  // Chunks keep memory flat on multi-GB impact sets.
  std::vector<char> buf(1 << 16);
  while (f) {
    f.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(f.gcount());
    h = fnv1a(std::string_view(buf.data(), n), h);
    bytes += n;
  }
  if (f.bad()) throw InputError(path, 0, option, "read failed");
  return {{"file", path}, {"bytes", bytes}, {"fnv1a64", fmt::format("{:016x}", h)}};
}

}  // namespace ricochet
