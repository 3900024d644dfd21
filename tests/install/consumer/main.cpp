// Links the installed libraries: one collision with the paper's law, and the lab's incident
// states read from the data folder that RICOCHET_DATA_DIR names (a program outside the install
// prefix finds the shipped files that way; docs/building.md).
#include <iostream>

#include "common/paths.hpp"
#include "diagnosis/synth.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

int main() {
  const ricochet::Model model = ricochet::Model::paper();
  const ricochet::Shape shape = ricochet::Shape::cylinder();
  ricochet::CollisionCase c;
  c.vin = {2.9, -2.3, -65.0};
  const ricochet::CollisionResult r = ricochet::simulate(model, shape, c);
  std::cout << "vout " << r.vout[0] << " " << r.vout[1] << " " << r.vout[2] << " ["
            << ricochet::status_name(r.status) << "]\n";
  const ricochet::ImpactSet lab = ricochet::diagnosis::lab_incident_states(shape);
  std::cout << lab.size() << " lab releases from " << ricochet::data_dir().string() << "\n";
  return r.status == ricochet::CollisionStatus::kOk ? 0 : 1;
}
