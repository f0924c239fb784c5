#include "writable_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sculpt::deform {

void check_writable(const PointModel& model, const char* writer) {
  model.validate();
  for (std::size_t i = 0; i < model.nx.size(); ++i) {
    if (!std::isfinite(model.nx[i]) || !std::isfinite(model.ny[i]) || !std::isfinite(model.nz[i])) {
      throw std::invalid_argument(std::string(writer) + ": point " + std::to_string(i) + " has a non-finite normal");
    }
  }
}

}  // namespace sculpt::deform
