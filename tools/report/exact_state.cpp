#include "exact_state.hpp"

#include <stdexcept>

namespace sculpt::tools::report {

ExactState ExactState::from(const deform::PointModel& model) {
  ExactState s;
  s.position.resize(model.size());
  for (std::size_t i = 0; i < model.size(); ++i) s.position[i] = model.position(i);
  if (model.has_normals()) {
    s.normal.resize(model.size());
    for (std::size_t i = 0; i < model.size(); ++i) s.normal[i] = model.normal(i);
  }
  return s;
}

void ExactState::store(deform::PointModel& model) const {
  if (model.size() != size() || model.has_normals() != has_normals()) {
    throw std::invalid_argument("report: the float model does not match the exact state's size or normals");
  }
  for (std::size_t i = 0; i < size(); ++i) model.set_position(i, position[i]);
  for (std::size_t i = 0; i < normal.size(); ++i) model.set_normal(i, normal[i]);
}

}  // namespace sculpt::tools::report
