// Links against the installed library and checks one known sum: two aligned unit cubes.
#include <minksum/minksum.hpp>

#include <cstdio>

int main() {
  minksum::ConvexPolytope a, b;
  minksum::Box box;
  if (minksum::polytope_from_box(box, a) != minksum::Status::Ok) return 1;
  if (minksum::polytope_from_box(box, b) != minksum::Status::Ok) return 1;
  minksum::MinkowskiSum m;
  if (minksum::minkowski_sum(a, b, m) != minksum::Status::Ok) return 1;
  std::printf("V=%d E=%d F=%d\n", m.V, m.E, m.F);
  return (m.V == 8 && m.E == 12 && m.F == 6 && m.euler_ok) ? 0 : 1;
}
