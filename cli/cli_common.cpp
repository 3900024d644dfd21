#include "cli_common.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include <iostream>

#include "common/error.hpp"

namespace ricochet::cli {

void add_output_options(CLI::App* sub, OutputOptions& options) {
  sub->add_flag("--json", options.json, "Print one machine-readable JSON document on stdout");
  sub->add_option("--out", options.out, "Write results to FILE (.csv or .h5 by extension)");
}

void check_range(CLI::App* sub, const std::string& name, double lo, double hi) {
  // CLI11's own Range prints its bounds with %f (1e-7 becomes 0.000000): this one uses %g.
  const std::string range = fmt::format("[{:g}, {:g}]", lo, hi);
  sub->get_option(name)->check(CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!(v >= lo && v <= hi)) return "value " + text + " is outside " + range;
        return {};
      },
      "in " + range));
}

namespace {
std::string& current_command() {
  static std::string command;
  return command;
}
}  // namespace

void set_current_command(std::string command) {
  current_command() = std::move(command);
}

nlohmann::json stamp_json(nlohmann::json doc) {
  if (!doc.is_object()) return doc;
  if (!doc.contains("command")) doc["command"] = current_command();
  if (!doc.contains("version")) doc["version"] = kVersion;
  return doc;
}

void print_json(const nlohmann::json& doc) {
  std::cout << stamp_json(doc).dump(2) << std::endl;
}

void require_extension(const std::string& option, const std::string& path,
                       std::initializer_list<const char*> allowed) {
  std::string list;
  for (const char* ext : allowed) {
    if (path.size() >= std::string(ext).size() &&
        path.compare(path.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      return;
    list += std::string(list.empty() ? "" : ", ") + ext;
  }
  throw InputError(path, 0, option, "unsupported file extension; use one of " + list);
}

void write_text_file(const std::string& path, const std::string& text, const std::string& option) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw InputError(path, 0, option, "cannot open the file for writing");
    f << text;
    if (!f.flush()) throw InputError(path, 0, option, "write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path, 0, option, "cannot move the written file into place");
  }
}

}  // namespace ricochet::cli
