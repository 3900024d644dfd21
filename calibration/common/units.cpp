#include "common/units.hpp"

#include <array>
#include <numbers>

namespace ricochet::units {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

const std::array<Unit, 14> kUnits = {{
    {"m/s", Dim::kVelocity, 1.0},
    {"cm/s", Dim::kVelocity, 1e-2},
    {"mm/s", Dim::kVelocity, 1e-3},
    {"rad/s", Dim::kAngularVelocity, 1.0},
    {"deg/s", Dim::kAngularVelocity, kDeg},
    {"rpm", Dim::kAngularVelocity, 2.0 * std::numbers::pi / 60.0},
    {"m", Dim::kLength, 1.0},
    {"cm", Dim::kLength, 1e-2},
    {"mm", Dim::kLength, 1e-3},
    {"s", Dim::kTime, 1.0},
    {"ms", Dim::kTime, 1e-3},
    {"rad", Dim::kAngle, 1.0},
    {"deg", Dim::kAngle, kDeg},
    {"-", Dim::kDimensionless, 1.0},
}};

}  // namespace

const Unit* find_unit(std::string_view name) {
  for (const auto& u : kUnits)
    if (name == u.name) return &u;
  return nullptr;
}

const Unit* find_unit(std::string_view name, Dim dim) {
  const Unit* u = find_unit(name);
  return u && u->dim == dim ? u : nullptr;
}

const char* si_unit(Dim dim) {
  switch (dim) {
    case Dim::kVelocity:
      return "m/s";
    case Dim::kAngularVelocity:
      return "rad/s";
    case Dim::kLength:
      return "m";
    case Dim::kTime:
      return "s";
    case Dim::kAngle:
      return "rad";
    case Dim::kDimensionless:
      return "-";
    case Dim::kText:
      return "";
  }
  return "";
}

const char* dim_name(Dim dim) {
  switch (dim) {
    case Dim::kVelocity:
      return "velocity";
    case Dim::kAngularVelocity:
      return "angular velocity";
    case Dim::kLength:
      return "length";
    case Dim::kTime:
      return "time";
    case Dim::kAngle:
      return "angle";
    case Dim::kDimensionless:
      return "dimensionless";
    case Dim::kText:
      return "text";
  }
  return "";
}

std::string units_of(Dim dim) {
  std::string out;
  for (const auto& u : kUnits) {
    if (dim != Dim::kText && u.dim != dim) continue;
    if (!out.empty()) out += ", ";
    out += u.name;
  }
  return out;
}

}  // namespace ricochet::units
