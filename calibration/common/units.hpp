// The one unit table of the readers of measured data: the impact-set CSV (impact/impact_csv.cpp,
// header cells `name[unit]`) and the track CSV (kinematics/reconstruct.cpp) accept the same units
// with the same factors to SI, so a length in mm or an angle in deg means one thing everywhere.
#pragma once

#include <string>
#include <string_view>

namespace ricochet::units {

/// Physical dimension of a column; fixes which units it accepts and its SI unit. kText is a
/// column without a unit (ids, labels).
enum class Dim { kVelocity, kAngularVelocity, kLength, kTime, kAngle, kDimensionless, kText };

/// A unit the readers accept: value_SI = value_in_file * to_si.
struct Unit {
  const char* name;  ///< as written between the brackets, e.g. "mm/s"
  Dim dim;
  double to_si;
};

/// The unit named `name` (exact, case-sensitive), or nullptr if unknown.
const Unit* find_unit(std::string_view name);
/// The unit named `name` if it measures `dim`, else nullptr (unknown, or another dimension).
const Unit* find_unit(std::string_view name, Dim dim);
/// SI unit of a dimension, the one the writers emit ("m/s", "rad/s", "m", "s", "rad", "-"; ""
/// for kText).
const char* si_unit(Dim dim);
/// The accepted units of `dim`, in table order, for messages: "m/s, cm/s, mm/s"; every known
/// unit when dim is kText.
std::string units_of(Dim dim);
/// "velocity", "angular velocity", "length", ... for messages.
const char* dim_name(Dim dim);

}  // namespace ricochet::units
