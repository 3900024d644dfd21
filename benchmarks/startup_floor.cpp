// The start-up floor of a process, for ./run.sh bench's start-up section: built twice, with no
// library and with OpenTURNS linked in (startup_floor_openturns), whose loading (its own
// relocations and those of its ~70 dependencies) is a floor for every command that samples or
// tests with it, the Monte Carlo among them.
#if RICOCHET_FLOOR_OPENTURNS
#include <openturns/OT.hxx>
#endif

int main() {
#if RICOCHET_FLOOR_OPENTURNS
  // One call, so the library stays linked whatever the linker's --as-needed default.
  return OT::DistFunc::qNormal(0.5) == 0.0 ? 0 : 1;
#else
  return 0;
#endif
}
