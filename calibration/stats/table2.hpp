// Paper Table 2 of an impact set, and the stats module's output layer: the table as JSON, CSV,
// HDF5 and text, in one place (`ricochet stats`; docs/commands/stats.md lists keys and columns).
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "impact/impact_set.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {

/// One column of paper Table 2: an impact-set feature with its unit and printed label.
struct Table2Column {
  const char* name;   ///< impact-set feature (impact/impact_set.hpp)
  const char* unit;   ///< m/s or rad/s
  const char* label;  ///< as the paper heads it
};
/// The six velocities in the column order of paper Table 2.
inline constexpr std::array<Table2Column, 6> kTable2Columns = {{
    {"vin_x", "m/s", "V_in^x"},
    {"vout_x", "m/s", "V_out^x"},
    {"vin_y", "m/s", "V_in^y"},
    {"vout_y", "m/s", "V_out^y"},
    {"win", "rad/s", "omega_in"},
    {"wout", "rad/s", "omega_out"},
}};

/// Mean, sample std (n - 1), signed cv, min and max of each Table 2 column of `set`.
struct Table2 {
  std::string source;  ///< the impact set's file
  std::string where;   ///< the filter applied ("" = every release)
  std::size_t n = 0;   ///< releases
  std::array<Summary, 6> columns;
};
Table2 table2(const ImpactSet& set, const std::string& source, const std::string& where);

/// JSON keys: "source", "n", "where" (null when empty), "columns" {NAME: {mean, std, cv, min,
/// max, unit}}. NaN (the std of one release) is written as null.
nlohmann::json to_json(const Table2& table);
/// One row per column: column, unit, n, mean, std, cv, min, max.
void write_csv(const std::string& path, const Table2& table);
/// /stats/{column, unit, n, mean, std, cv, min, max} with source, where, releases attributes.
void write_h5(const std::string& path, const Table2& table);
/// The table as the command prints it (the paper's layout, one column per velocity).
std::string format_text(const Table2& table);

}  // namespace ricochet::stats
