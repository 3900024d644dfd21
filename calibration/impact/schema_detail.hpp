// Internal to the impact module: the column table, units and per-impact checks shared by the
// CSV reader/writer, the HDF5 reader/writer and validate(). Not part of the public API.
//
// This header (and impact_set.cpp, impact_csv.cpp) must not depend on HDF5: the fuzz target
// compiles them alone with clang (see fuzz/README.md).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "common/csv.hpp"
#include "common/units.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::impact_detail {

// The unit table is the one shared with the track reader (common/units.hpp).
using units::Dim;
using units::dim_name;
using units::find_unit;
using units::si_unit;
using units::Unit;
using units::units_of;

/// Schema columns other than extras, in the order the writers emit them.
enum class Col {
  kId,
  kShape,
  kVinX,
  kVinY,
  kWin,
  kVoutX,
  kVoutY,
  kWout,
  kAlphaIn,
  kPenetration,
  kContactDuration,
  kOperator,
  kReplicate,
  kWeight,
  kSigmaVinX,
  kSigmaVinY,
  kSigmaVinW,
  kSigmaVoutX,
  kSigmaVoutY,
  kSigmaVoutW,
};
struct ColumnSpec {
  Col col;
  const char* name;
  Dim dim;
  bool required;
};
/// All schema columns in writer order.
const std::vector<ColumnSpec>& schema_columns();
/// The schema column named `name`, or nullptr (then the column is an extra feature).
const ColumnSpec* find_column(std::string_view name);
/// Names that extras may not take: schema columns plus derived features (speed_in).
bool is_reserved_name(std::string_view name);
/// Column names are identifiers: [A-Za-z0-9_]+ (they become HDF5 dataset names and JSON keys).
bool is_valid_column_name(std::string_view name);

/// Numeric value of a schema column for one impact (nullopt when the optional field is absent).
std::optional<double> get_numeric(const Impact& impact, Col col);
/// Sets a numeric schema column; sigma components create the triple (zeros) on first use.
void set_numeric(Impact& impact, Col col, double value_si);
/// True when the impact carries this optional column.
bool has_column(const Impact& impact, Col col);

/// Checks the invariants of one impact (not the uniqueness of its id) and throws InputError(file,
/// line, field, ...) on the first violation. `n_extra` is the expected size of impact.extra.
/// `incident_only` (read_incident_states): an impact whose three vout components are all NaN is
/// an incident state, and its reflected velocity is not checked.
void check_impact(const Impact& impact, std::size_t n_extra, const std::string& file,
                  std::size_t line, bool incident_only = false);
/// Checks extra_names / extra_units of a set (names valid, unique, not reserved; SI units).
void check_extras_declaration(const ImpactSet& set, const std::string& file, std::size_t line);

/// Assembles one row (a CSV line or an HDF5 row) into an Impact with the same rules for both
/// file forms: numeric cells in SI, the all-or-none rule of the uncertainty triplets, the schema
/// invariants and unique ids. `missing` words the error for an absent sigma component ("empty
/// cell" in CSV, "value is NaN" in HDF5); `place` names the first occurrence of an id ("line",
/// "row").
class RowAssembler {
 public:
  /// `incident_only`: rows without a reflected velocity (NaN vout) are accepted (check_impact).
  RowAssembler(std::string file, const char* missing, const char* place, bool incident_only = false)
      : file_(std::move(file)), missing_(missing), place_(place), incident_only_(incident_only) {}
  /// Stores one numeric value (SI) of a schema column (`spec`) or of extra column `extra_index`.
  void store(Impact& impact, const ColumnSpec* spec, std::size_t extra_index, double value_si);
  /// Checks the row (n_extra extra columns expected) and appends it to `set`.
  void finish(Impact&& impact, ImpactSet& set, std::size_t line);

 private:
  std::string file_;
  const char* missing_;
  const char* place_;
  bool incident_only_ = false;
  std::array<std::array<bool, 3>, 2> sigma_given_{};
  std::unordered_map<std::string, std::size_t> id_line_;
};

/// Parses a whole cell as a double (std::from_chars, optional leading '+'); false if any
/// character is left over or the value is out of range. NaN/inf parse: the caller checks.
bool parse_number(std::string_view text, double& value);

/// Trims spaces, tabs, CR, VT and FF on both sides (the CSV cell rule, common/csv.hpp).
inline std::string_view trim(std::string_view text) {
  return csv_trim(text);
}

}  // namespace ricochet::impact_detail
