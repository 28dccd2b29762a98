// Python access to the load histories the engine applies, so that Python
// code plotting or checking them uses the engine's own formula.
#include <pybind11/numpy.h>

#include "bindings/bindings.hpp"
#include "common/input_errors.hpp"
#include "loads/boundary_conditions.hpp"

namespace py = pybind11;

namespace engine {

void bind_loads(py::module_& m) {
  m.def(
      "ramp_velocity",
      [](py::object t, double v_final, double ramp_time) {
        if (!std::isfinite(v_final)) bad("v_final must be finite (got " + num(v_final) + ")");
        require_finite_nonnegative("ramp_time", ramp_time, "s (0: v_final from the start)");
        return py::vectorize([v_final, ramp_time](double time) {
          return ramp_velocity(time, v_final, ramp_time);
        })(py::array_t<double, py::array::forcecast>::ensure(t));
      },
      py::arg("t"), py::arg("v_final"), py::arg("ramp_time"),
      "Speed of prescribe_velocity(v_final, ramp_time) at time(s) t [m/s]: the smooth ramp\n"
      "v_f (t/T - sin(2 pi t/T)/(2 pi)) for 0 < t < T, 0 before, v_final after.");
}

}  // namespace engine
