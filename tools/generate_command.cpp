// sculpt generate: writes the built-in test shapes (the thesis's sphere, a plane, a box).
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::tools {
namespace {

class GenerateCommand final : public Command {
 public:
  explicit GenerateCommand(CLI::App& app) {
    sub_ = app.add_subcommand("generate", "Write a built-in test model (sphere, plane or box) as PLY");
    sub_->add_option("shape", shape_, "sphere | plane | box")
        ->required()
        ->check(CLI::IsMember({"sphere", "plane", "box"}));
    sub_->add_option("--out", out_, "Output file (.ply, .off or .xyz)")->required();
    sub_->add_option("--points", points_, "Sphere: number of points (the thesis used 3,203)")
        ->check(CLI::Range(4, 100000000));
    sub_->add_option("--radius", radius_, "Sphere radius")->check(CLI::PositiveNumber);
    sub_->add_option("--per-side", per_side_, "Plane: points per side")->check(CLI::Range(2, 100000));
    sub_->add_option("--spacing", spacing_, "Plane and box: point spacing")->check(CLI::PositiveNumber);
  }
  bool chosen() const override { return sub_->parsed(); }
  int run() override {
    try {
      deform::PointModel model;
      if (shape_ == "sphere") model = deform::make_sphere(points_, radius_);
      if (shape_ == "plane") model = deform::make_plane_patch(per_side_, spacing_);
      if (shape_ == "box") model = deform::make_box({1.0, 1.0, 1.0}, spacing_);
      deform::write_model(out_, model);
      std::cout << "wrote " << out_ << ": " << model.size() << " points with normals\n";
      return kExitOk;
    } catch (const std::exception& e) {
      std::cerr << "sculpt generate: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  CLI::App* sub_ = nullptr;
  std::string shape_, out_;
  std::size_t points_ = 3203, per_side_ = 101;
  double radius_ = 1.0, spacing_ = 0.02;
};

}  // namespace

std::unique_ptr<Command> add_generate_command(CLI::App& app) { return std::make_unique<GenerateCommand>(app); }

}  // namespace sculpt::tools
