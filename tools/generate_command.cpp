// sculpt generate: writes the built-in test shapes (the thesis's sphere, a plane, a box).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "commands.hpp"
#include "number_check.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::tools {
namespace {

/// Model files refuse coordinates of 1e18 and beyond (their squares leave float's range).
constexpr double kMaxExtent = 1e18;

/// The intervals per edge of the unit box whose surface grid, 6 m^2 + 2 points, comes nearest
/// to `points`.
std::size_t box_intervals(std::size_t points) {
  const double m = std::round(std::sqrt(std::max(0.0, static_cast<double>(points) - 2.0) / 6.0));
  return static_cast<std::size_t>(std::max(1.0, m));
}

class GenerateCommand final : public Command {
 public:
  explicit GenerateCommand(CLI::App& app) {
    sub_ = app.add_subcommand("generate", "Write a built-in test model (sphere, plane or box) as PLY");
    sub_->add_option("shape", shape_, "sphere | plane | box")
        ->required()
        ->check(CLI::IsMember({"sphere", "plane", "box"}));
    sub_->add_option("--out", out_, "Output file (.ply, .off or .xyz)")->required();
    points_option_ = sub_->add_option("--points", points_,
                                      "Sphere: number of points (the thesis used 3,203); box: about this many "
                                      "(the nearest regular grid)")
                         ->check(CLI::Range(4, 100000000));
    radius_option_ = sub_->add_option("--radius", radius_, "Sphere radius")
                         ->check(finite_in(0.0, true, kMaxExtent, true, "coordinates stay below 1e18"));
    per_side_option_ =
        sub_->add_option("--per-side", per_side_, "Plane: points per side (at most 10,000: 1e8 points, as --points)")
            ->check(CLI::Range(2, 10000));
    spacing_option_ = sub_->add_option("--spacing", spacing_, "Plane and box: point spacing")
                          ->check(finite_in(0.0, true, kMaxExtent, true, "coordinates stay below 1e18"));
  }
  bool chosen() const override { return sub_->parsed(); }
  int run() override {
    try {
      refuse_unused_options();
      // Up to a hundred million points are made before anything is written: a name or a folder
      // that cannot take them is found first.
      refuse_unwritable_output({"--out", out_});
      refuse_unwritable_model_format("--out", out_);
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt generate: error: " << e.what() << "\n";
      return kExitUsage;
    }
    try {
      deform::PointModel model;
      std::string note;
      if (shape_ == "sphere") model = deform::make_sphere(points_, radius_);
      if (shape_ == "plane") model = deform::make_plane_patch(per_side_, spacing_);
      if (shape_ == "box") {
        double spacing = spacing_;
        if (points_option_->count()) {
          const std::size_t m = box_intervals(points_);
          spacing = 1.0 / static_cast<double>(m);
          note = " (" + std::to_string(m) + " intervals per edge: the box grid nearest to --points " +
                 std::to_string(points_) + ")";
        }
        model = deform::make_box({1.0, 1.0, 1.0}, spacing);
      }
      write_model_output(out_, model);
      std::cout << "wrote " << out_ << ": " << model.size() << " points with normals" << note << "\n";
      return kExitOk;
    } catch (const std::exception& e) {
      std::cerr << "sculpt generate: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  // Each shape has its own size options; one given for another shape would be silently ignored
  // (`generate box --points` was), so it is refused, naming what the shape takes.
  void refuse_unused_options() const {
    struct Use {
      const CLI::Option* option;
      const char* name;
      std::vector<std::string> shapes;
    };
    const Use uses[] = {{points_option_, "--points", {"sphere", "box"}},
                        {radius_option_, "--radius", {"sphere"}},
                        {per_side_option_, "--per-side", {"plane"}},
                        {spacing_option_, "--spacing", {"plane", "box"}}};
    const char* takes = shape_ == "sphere"  ? "--points and --radius"
                        : shape_ == "plane" ? "--per-side and --spacing"
                                            : "--points or --spacing";
    for (const Use& use : uses) {
      if (use.option->count() == 0) continue;
      if (std::find(use.shapes.begin(), use.shapes.end(), shape_) == use.shapes.end()) {
        throw std::invalid_argument(std::string(use.name) + " is not used by " + shape_ + " (it takes " + takes + ")");
      }
    }
    // Both fix the box's grid: one would be ignored.
    if (shape_ == "box" && points_option_->count() && spacing_option_->count()) {
      throw std::invalid_argument("--points and --spacing both set the box's grid: give one");
    }
  }

  CLI::App* sub_ = nullptr;
  CLI::Option *points_option_ = nullptr, *radius_option_ = nullptr, *per_side_option_ = nullptr,
              *spacing_option_ = nullptr;
  std::string shape_, out_;
  std::size_t points_ = 3203, per_side_ = 101;
  double radius_ = 1.0, spacing_ = 0.02;
};

}  // namespace

std::unique_ptr<Command> add_generate_command(CLI::App& app) { return std::make_unique<GenerateCommand>(app); }

}  // namespace sculpt::tools
