#include "cli_common.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include <iostream>
#include <set>

#include "common/error.hpp"
#include "common/provenance.hpp"

namespace ricochet::cli {

namespace {
struct CurrentCommand {
  std::string name;
  const CLI::App* parser = nullptr;
  std::optional<nlohmann::json> input_files;  // hashed once per run, however many documents
  std::string json_file;                      // --out FILE.json
  bool json_stdout = false;                   // --json given with --out FILE.json
};
CurrentCommand& current_command() {
  static CurrentCommand command;
  return command;
}
}  // namespace

void add_output_options(CLI::App* sub, OutputOptions& options, JsonOut json_out) {
  // --json is declared first: CLI11 runs option callbacks in declaration order, so --out's
  // function below sees whether --json was given.
  sub->add_flag("--json", options.json, "Print one machine-readable JSON document on stdout");
  options.accepts_json_file = json_out == JsonOut::kAccepted;
  if (!options.accepts_json_file) {
    sub->add_option("--out", options.out, "Write results to FILE (by extension)");
    return;
  }
  sub->add_option_function<std::string>(
         "--out",
         [&options](const std::string& path) {
           if (!path.ends_with(".json")) {
             options.out = path;
             return;
           }
           current_command().json_file = path;
           current_command().json_stdout = options.json;
           options.json = true;
         },
         "Write results to FILE (.csv, .h5 or .json by extension)")
      ->type_name("FILE");
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

void refuse_problems(const OptionProblems& problems, const OptionNames& names) {
  if (problems.empty()) return;
  const OptionProblem& first = problems.front();
  std::string option = first.option;
  for (const auto& [field, name] : names)
    if (field == first.option) option = name;
  throw InputError("<command line>", 0, option, first.message);
}

void show_range(CLI::App* sub, const std::string& name, const OptionRange& range) {
  // A validator CLI11 shows in --help. It refuses a non-number with check_range's message rather
  // than CLI11's conversion error, and a negative number for an unsigned option: CLI11 would wrap
  // it into a huge value (-5 into 1.8e19) before the library saw it.
  CLI::Option* option = sub->get_option(name);
  const bool is_unsigned = option->get_type_name().starts_with("UINT");
  option->check(CLI::Validator(
      [range, is_unsigned](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (is_unsigned && v < 0) return "value " + text + " is outside " + range.text();
        return {};
      },
      "in " + range.text()));
}

OptionRange degrees(const OptionRange& radians) {
  OptionRange d = radians;
  d.lo = radians.lo * 180 / M_PI;
  d.hi = radians.hi * 180 / M_PI;
  return d;
}

void refuse_degrees(const std::string& name, const std::vector<double>& values,
                    const OptionRange& radians) {
  OptionProblems problems;
  for (double v : values) check_range(problems, name, v, degrees(radians));
  refuse_problems(problems, {});
}

void set_current_command(std::string command, const CLI::App* parser) {
  current_command() = {std::move(command), parser, std::nullopt, {}, false};
}

nlohmann::json input_files() {
  auto& cached = current_command().input_files;
  if (cached) return *cached;
  nlohmann::json files = nlohmann::json::array();
  const CLI::App* parser = current_command().parser;
  if (!parser) return files;
  std::set<std::string> seen;
  for (const CLI::Option* opt : parser->get_options()) {
    const std::string name = opt->get_name();
    if (name == "--out" || name == "--write-model" || name == "--write-force-model" ||
        name == "--truth")
      continue;
    for (const std::string& value : opt->results()) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(value, ec) || !seen.insert(value).second) continue;
      nlohmann::json p = file_provenance(value, name);
      p["option"] = name;
      files.push_back(std::move(p));
    }
  }
  cached = files;
  return files;
}

nlohmann::json stamp_json(nlohmann::json doc) {
  if (!doc.is_object()) return doc;
  if (!doc.contains("command")) doc["command"] = current_command().name;
  if (!doc.contains("version")) doc["version"] = kVersion;
  if (!doc.contains("input_files")) doc["input_files"] = input_files();
  return doc;
}

void print_json(const nlohmann::json& doc) {
  nlohmann::json stamped = stamp_json(doc);
  const CurrentCommand& c = current_command();
  if (!c.json_file.empty()) {
    if (stamped.is_object() && stamped.contains("out")) stamped["out"] = c.json_file;
    write_text_file(c.json_file, stamped.dump(2) + "\n", "--out");
    if (!c.json_stdout) {
      std::cout << "wrote " << c.json_file << std::endl;
      return;
    }
  }
  std::cout << stamped.dump(2) << std::endl;
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

void require_out_extension(const OutputOptions& options,
                           std::initializer_list<const char*> allowed) {
  if (options.out.empty()) return;
  std::string list;
  for (const char* ext : allowed) {
    if (options.out.ends_with(ext)) return;
    list += std::string(list.empty() ? "" : ", ") + ext;
  }
  if (options.accepts_json_file) list += std::string(list.empty() ? "" : ", ") + ".json";
  throw InputError(options.out, 0, "--out", "unsupported file extension; use one of " + list);
}

}  // namespace ricochet::cli
