#pragma once
// The elastic kernels of MATH.md §1-2: displacement, its gradient, and surface traction of a
// point force in an infinite homogeneous isotropic solid.

#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

/// Isotropic linear-elastic material.
/// Largest shear modulus accepted. The solved forces grow with G (a force moving a point by a
/// length L at distance R is about G L R), so past this they, and their products with model
/// lengths, leave the range the float loop can carry.
inline constexpr double kMaxShearModulus = 1e15;
/// Smallest shear modulus accepted, for the same reason at the other end: the forces shrink with
/// G, and on the bundled sphere a G of 1e-36 made every frame non-finite (each undone by the
/// guard, so the station sculpted nothing), where 1e-30 still pressed as 3e7 does. Softer than
/// any material in any units (a hydrogel is about 10 Pa, 1e-5 N/mm²).
inline constexpr double kMinShearModulus = 1e-15;

struct Material {
  double shear_modulus = 3e7;   ///< G, in force per area of the model's units; in [kMinShearModulus, kMaxShearModulus]
  double poisson_ratio = 0.45;  ///< nu, in (-1, 0.5]; 0.5 is the incompressible limit

  double young_modulus() const { return 2.0 * shear_modulus * (1.0 + poisson_ratio); }
  /// Throws std::invalid_argument naming the bad value.
  void validate() const;
};

enum class KernelKind {
  kKelvin,       ///< the thesis's singular Kelvin solution
  kRegularized,  ///< de Goes and James's regularized Kelvinlet, finite at R = 0
};

/// A kernel with its material. Nothing ever swaps one kind for the other silently.
struct Kernel {
  KernelKind kind = KernelKind::kKelvin;
  Material material;
  double regularization = 0.0;  ///< eps of the regularized Kelvinlet (model units); must be > 0 for it

  void validate() const;
};

/// Every kernel here has the form u = (alpha/r + beta/r^3) f + gamma/r^3 (r.f) r with
/// r^2 = R^2 + eps^2 (eps = 0 for Kelvin). These are those coefficients, precomputed once so
/// the hot loop reads four numbers instead of branching on the kernel kind.
struct KernelCoefficients {
  double alpha = 0.0;
  double beta = 0.0;
  double gamma = 0.0;
  double eps_squared = 0.0;
  /// lambda * div u = (r.f) (lambda_div3 / r^3 + lambda_div5 / r^5); the factor 1 - 2 nu that
  /// lambda divides by is cancelled analytically, so stresses stay finite at nu = 0.5.
  double lambda_div3 = 0.0;
  double lambda_div5 = 0.0;
};

KernelCoefficients coefficients(const Kernel& kernel);

/// Row-major 3x3 matrix.
struct Mat3 {
  double m[3][3] = {};
  double operator()(int r, int c) const { return m[r][c]; }
  double& operator()(int r, int c) { return m[r][c]; }
};

/// U_kl(P, Q): displacement at Q in direction l per unit force at P in direction k. Symmetric.
Mat3 displacement_matrix(const Kernel& kernel, const Vec3& source, const Vec3& point);
/// The same from precomputed coefficients, for loops over many points.
Mat3 displacement_matrix(const KernelCoefficients& k, const Vec3& source, const Vec3& point);
/// u(Q) = sum_k f_k U_kl(P, Q).
Vec3 displacement(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point);
/// grad(l, m) = d u_l / d Q_m.
Mat3 displacement_gradient(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point);
/// sigma(Q) n with sigma = lambda tr(eps) I + 2 G eps built from the analytic gradient; works for
/// both kernels and at nu = 0.5.
Vec3 stress_traction(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point,
                     const Vec3& normal);

/// T_ij(P, Q, n) of MATH.md §2 for the Kelvin kernel: i is the force direction, j the traction
/// component, so t = T^T f. Independent of G.
Mat3 kelvin_traction_matrix(double poisson_ratio, const Vec3& source, const Vec3& point, const Vec3& normal);
/// t_j(Q, n) = sum_i f_i T_ij(P, Q, n).
Vec3 kelvin_traction(double poisson_ratio, const Vec3& source, const Vec3& force, const Vec3& point,
                     const Vec3& normal);

/// The traction the kernel prescribes: MATH.md §2's closed form for Kelvin, the stress of the
/// analytic gradient for the regularized kernel.
Vec3 traction(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point, const Vec3& normal);
/// The 3x3 map f -> traction for one source (its transpose is the T of §2 for Kelvin).
Mat3 traction_map(const Kernel& kernel, const Vec3& source, const Vec3& point, const Vec3& normal);

}  // namespace sculpt::deform
