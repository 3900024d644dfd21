// Provenance of results: the one content hash of the project (FNV-1a 64) and the record of an
// input file that every JSON document carries ("input_files", docs/commands/README.md).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace ricochet {

/// FNV-1a 64 (Fowler-Noll-Vo; offset basis and prime of the published 64-bit variant) of `text`,
/// continuing from `h`. It names content (cache keys, replicate labels, input digests); it is not
/// cryptographic and protects nothing.
inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
std::uint64_t fnv1a(std::string_view text, std::uint64_t h = kFnvOffset);

/// The provenance of the input file `path`: {"file": path, "bytes": size, "fnv1a64": 16 hex
/// digits of the content's hash}. Throws InputError(path, 0, option, ...) when it cannot be read.
nlohmann::json file_provenance(const std::string& path, const std::string& option = "");

}  // namespace ricochet
