#include "stats/table2.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "common/csv.hpp"
#include "common/h5.hpp"

namespace ricochet::stats {

Table2 table2(const ImpactSet& set, const std::string& source, const std::string& where) {
  Table2 t;
  t.source = source;
  t.where = where;
  t.n = set.size();
  for (std::size_t k = 0; k < kTable2Columns.size(); ++k)
    t.columns[k] = summarize(set.feature(kTable2Columns[k].name));
  return t;
}

nlohmann::json to_json(const Table2& t) {
  nlohmann::json doc;
  doc["source"] = t.source;
  doc["n"] = t.n;
  doc["where"] = t.where.empty() ? nlohmann::json(nullptr) : nlohmann::json(t.where);
  nlohmann::json columns = nlohmann::json::object();
  for (std::size_t k = 0; k < kTable2Columns.size(); ++k) {
    const Summary& s = t.columns[k];
    // nlohmann::json writes NaN (e.g. std of a single release) as null.
    columns[kTable2Columns[k].name] = {{"mean", s.mean}, {"std", s.std},
                                       {"cv", s.cv},     {"min", s.min},
                                       {"max", s.max},   {"unit", kTable2Columns[k].unit}};
  }
  doc["columns"] = columns;
  return doc;
}

void write_csv(const std::string& path, const Table2& t) {
  CsvTable csv;
  csv.comment(fmt::format("ricochet stats of {} ({} releases)", t.source, t.n));
  if (!t.where.empty()) csv.comment("where: " + t.where);
  csv.comment("std: sample standard deviation (n - 1); cv = std / mean (signed)");
  csv.row({"column", "unit", "n", "mean", "std", "cv", "min", "max"});
  for (std::size_t k = 0; k < kTable2Columns.size(); ++k) {
    const Summary& s = t.columns[k];
    csv.row({kTable2Columns[k].name, kTable2Columns[k].unit, std::to_string(s.n),
             CsvTable::num(s.mean), CsvTable::num(s.std), CsvTable::num(s.cv), CsvTable::num(s.min),
             CsvTable::num(s.max)});
  }
  csv.write(path);
}

void write_h5(const std::string& path, const Table2& t) {
  h5::File file(path, h5::File::Mode::kTruncate);
  std::vector<std::string> names, units;
  std::vector<double> count, mean, sd, cv, min, max;
  for (std::size_t k = 0; k < kTable2Columns.size(); ++k) {
    const Summary& s = t.columns[k];
    names.emplace_back(kTable2Columns[k].name);
    units.emplace_back(kTable2Columns[k].unit);
    count.push_back(static_cast<double>(s.n));
    mean.push_back(s.mean);
    sd.push_back(s.std);
    cv.push_back(s.cv);
    min.push_back(s.min);
    max.push_back(s.max);
  }
  file.write_strings("/stats/column", names);
  file.write_strings("/stats/unit", units);
  file.write("/stats/n", count);
  file.write("/stats/mean", mean);
  file.write("/stats/std", sd);
  file.write("/stats/cv", cv);
  file.write("/stats/min", min);
  file.write("/stats/max", max);
  file.set_attr("/stats", "source", t.source);
  file.set_attr("/stats", "where", t.where);
  file.set_attr("/stats", "releases", static_cast<double>(t.n));
  file.flush();
}

std::string format_text(const Table2& t) {
  std::string out = fmt::format("{} ({} releases{})\n", t.source, t.n,
                                t.where.empty() ? std::string() : ", where " + t.where);
  std::string head = fmt::format("{:<10}", "");
  std::string units = head;
  for (const auto& c : kTable2Columns) {
    head += fmt::format("{:>11}", c.label);
    units += fmt::format("{:>11}", std::string("[") + c.unit + "]");
  }
  out += head + "\n" + units + "\n";
  auto row = [&](const char* label, auto value, const char* format) {
    std::string line = fmt::format("{:<10}", label);
    // An undefined cell (the std of one release, the V_out of a plan of throws) prints as "-".
    for (const Summary& s : t.columns)
      line += std::isfinite(value(s)) ? fmt::format(fmt::runtime(format), value(s))
                                      : fmt::format("{:>11}", "-");
    out += line + "\n";
  };
  row(
      "mean", [](const Summary& x) { return x.mean; }, "{:>11.3f}");
  row(
      "std", [](const Summary& x) { return x.std; }, "{:>11.3f}");
  row(
      "cv [%]", [](const Summary& x) { return 100.0 * x.cv; }, "{:>11.1f}");
  row(
      "min", [](const Summary& x) { return x.min; }, "{:>11.2f}");
  row(
      "max", [](const Summary& x) { return x.max; }, "{:>11.2f}");
  out += "std: sample standard deviation (n - 1); cv = std / mean, signed as in paper Table 2.\n";
  return out;
}

}  // namespace ricochet::stats
