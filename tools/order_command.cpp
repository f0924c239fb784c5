// sculpt order: writes a model with its points stored in Z order (spatial_order.hpp), so that a
// region frame finds a ball's points in few cache lines. Nothing but the storage order changes.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "commands.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/spatial_order.hpp"

namespace sculpt::tools {
namespace {

class OrderCommand final : public Command {
 public:
  explicit OrderCommand(CLI::App& app) {
    sub_ = app.add_subcommand("order",
                              "Write a model with its points stored in spatial (Z) order: faster region frames, "
                              "the same surface");
    sub_->add_option("model", in_, "Model to read (.ply, .off or .xyz)")->required();
    sub_->add_option("--out", out_, "Output file (.ply, .off or .xyz); faces are renumbered")->required();
  }
  bool chosen() const override { return sub_->parsed(); }
  int run() override {
    // --out may replace the model (it is written atomically): the same surface, reordered.
    try {
      refuse_unwritable_output({"--out", out_});
      refuse_unwritable_model_format("--out", out_);
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt order: error: " << e.what() << "\n";
      return kExitUsage;
    }
    try {
      const deform::PointModel model = deform::read_model(in_);
      const deform::PointModel ordered = deform::reordered(model, deform::spatial_order(model));
      const double before = deform::neighbour_locality(model, deform::PointIndex(model));
      const double after = deform::neighbour_locality(ordered, deform::PointIndex(ordered));
      write_model_output(out_, ordered);
      char line[160];
      std::snprintf(line, sizeof line, "wrote %s: %zu points in Z order; neighbours within a cache line %.2f -> %.2f",
                    out_.c_str(), ordered.size(), before, after);
      std::cout << line << "\n";
      return kExitOk;
    } catch (const std::exception& e) {
      std::cerr << "sculpt order: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  CLI::App* sub_ = nullptr;
  std::string in_, out_;
};

}  // namespace

std::unique_ptr<Command> add_order_command(CLI::App& app) { return std::make_unique<OrderCommand>(app); }

}  // namespace sculpt::tools
