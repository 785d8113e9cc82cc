// Gauss' least-constraint solver: closed forms, KKT conditions, and agreement
// with CGAL's exact quadratic-programming solver on random instances.
#include "algorithms/contact/gauss_least_constraint.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <Eigen/SVD>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hapticbench/input_error.h"

namespace hb {
namespace {

using Rng = std::mt19937_64;

double uniform(Rng& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

Vec3 random_unit(Rng& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 v;
  do {
    v = Vec3(normal(rng), normal(rng), normal(rng));
  } while (v.norm() < 1e-3);
  return v.normalized();
}

// A unit vector within `max_angle_rad` of `axis`: contact normals of a tool
// pressed against a surface spread around the surface's normal.
Vec3 random_unit_in_cone(Rng& rng, const Vec3& axis, double max_angle_rad) {
  while (true) {
    const Vec3 v = random_unit(rng);
    if (v.dot(axis) >= std::cos(max_angle_rad)) return v;
  }
}

Mat3 random_rotation(Rng& rng) {
  return Eigen::AngleAxisd(uniform(rng, 0, std::numbers::pi), random_unit(rng)).toRotationMatrix();
}

// A tool of 0.1–2 kg and a few centimetres, its inertia in rotated world axes.
Mat6 random_rigid_body_mass(Rng& rng) {
  const double mass = uniform(rng, 0.1, 2.0);
  const Vec3 extents(uniform(rng, 0.01, 0.06), uniform(rng, 0.01, 0.06), uniform(rng, 0.01, 0.06));
  const Vec3 e2 = extents.cwiseProduct(extents);
  const Vec3 principal = mass / 12.0 * Vec3(e2.y() + e2.z(), e2.x() + e2.z(), e2.x() + e2.y());
  const Mat3 rotation = random_rotation(rng);
  Mat3 inertia = rotation * principal.asDiagonal() * rotation.transpose();
  inertia = 0.5 * (inertia + inertia.transpose()).eval();
  return rigid_body_mass_matrix(mass, inertia);
}

// Any symmetric positive definite matrix, coupling all six coordinates.
Mat6 random_general_mass(Rng& rng) {
  Mat6 a;
  for (int i = 0; i < 36; ++i) a(i) = uniform(rng, -1, 1);
  Mat6 mass = a.transpose() * a + 0.1 * Mat6::Identity();
  return 0.5 * (mass + mass.transpose());
}

Vec6 random_unconstrained(Rng& rng, const Vec3& push_direction) {
  Vec6 a;
  a.head<3>() = -0.8 * push_direction + 0.5 * random_unit(rng) * uniform(rng, 0, 1);
  a.tail<3>() = uniform(rng, 0, 20) * random_unit(rng);  // rad/s²: α × r ~ 1 m/s²
  return a;
}

struct Instance {
  Mat6 mass;
  Vec6 unconstrained;
  std::vector<GaussConstraint> constraints;
  bool rhs_nonzero = false;
};

double objective(const Instance& instance, const Vec6& a) {
  const Vec6 d = a - instance.unconstrained;
  return 0.5 * d.dot(instance.mass * d);
}

// ---------------------------------------------------------------------------
// Exact reference: CGAL's QP solver over Gmpzf (exact binary floating point
// with unbounded precision). Program data are built in Gmpzf from the same
// double inputs, so the reference solves exactly the problem the solver sees.
// CGAL minimises xᵀDx + cᵀx + c0 and takes the entries of 2D, so 2D = M,
// c = −M a^u, c0 = ½ a^uᵀ M a^u gives ½ (x − a^u)ᵀ M (x − a^u).

using Exact = CGAL::Gmpzf;

struct ExactSolution {
  bool infeasible = false;
  double objective = 0;
  Vec6 acceleration = Vec6::Zero();
  std::vector<int> tight;     // constraints holding with exact equality
  std::vector<double> slack;  // J_k a* − b_k, rounded from the exact value
};

ExactSolution solve_exactly(const Instance& instance) {
  CGAL::Quadratic_program<Exact> program(CGAL::LARGER, false, Exact(0), false, Exact(0));
  const int count = static_cast<int>(instance.constraints.size());
  for (int k = 0; k < count; ++k) {
    const Vec6 row = constraint_row(instance.constraints[k]);
    for (int j = 0; j < 6; ++j) program.set_a(j, k, Exact(row[j]));
    program.set_b(k, Exact(instance.constraints[k].rhs));
  }
  Exact constant(0);
  for (int i = 0; i < 6; ++i) {
    Exact linear(0);
    for (int j = 0; j < 6; ++j) {
      if (j <= i) program.set_d(i, j, Exact(instance.mass(i, j)));
      linear = linear - Exact(instance.mass(i, j)) * Exact(instance.unconstrained[j]);
      constant = constant + Exact(0.5) * Exact(instance.unconstrained[i]) *
                                Exact(instance.mass(i, j)) * Exact(instance.unconstrained[j]);
    }
    program.set_c(i, linear);
  }
  program.set_c0(constant);
  const auto solution = CGAL::solve_quadratic_program(program, Exact());
  ExactSolution exact;
  if (solution.is_infeasible()) {
    exact.infeasible = true;
    return exact;
  }
  REQUIRE(solution.is_optimal());
  exact.objective = CGAL::to_double(solution.objective_value());
  std::vector<Exact> numerators(solution.variable_numerators_begin(),
                                solution.variable_numerators_end());
  REQUIRE(numerators.size() == 6);
  const Exact denominator = solution.variables_common_denominator();
  for (int j = 0; j < 6; ++j) {
    exact.acceleration[j] = CGAL::to_double(CGAL::Quotient<Exact>(numerators[j], denominator));
  }
  for (int k = 0; k < count; ++k) {
    const Vec6 row = constraint_row(instance.constraints[k]);
    Exact scaled_slack = -Exact(instance.constraints[k].rhs) * denominator;
    for (int j = 0; j < 6; ++j) scaled_slack = scaled_slack + Exact(row[j]) * numerators[j];
    if (CGAL::is_zero(scaled_slack)) exact.tight.push_back(k);
    exact.slack.push_back(CGAL::to_double(CGAL::Quotient<Exact>(scaled_slack, denominator)));
  }
  return exact;
}

// Whether the exact optimum is non-degenerate, so that its active set is a
// stable property of the problem: the tight rows are independent and well
// conditioned, each carries a clearly positive multiplier, and no other
// constraint is within rounding of tight. Otherwise (duplicate rows, four
// coplanar contacts, a* = 0 with more than six contacts, a weakly active
// constraint) the multipliers are not unique and any rounding can change
// which of the equivalent sets a solver returns, while the objective, the
// solution and feasibility stay well defined.
bool is_nondegenerate(const Instance& instance, const ExactSolution& exact) {
  const int tight = static_cast<int>(exact.tight.size());
  if (tight > 6) return false;
  const double scale = 1 + exact.acceleration.norm() + instance.unconstrained.norm();
  for (size_t k = 0; k < exact.slack.size(); ++k) {
    const bool is_tight =
        std::count(exact.tight.begin(), exact.tight.end(), static_cast<int>(k)) > 0;
    if (!is_tight && exact.slack[k] < 1e-8 * scale) return false;
  }
  if (tight == 0) return true;
  Eigen::MatrixXd rows(tight, 6);
  for (int i = 0; i < tight; ++i) {
    rows.row(i) = constraint_row(instance.constraints[exact.tight[i]]).transpose();
  }
  const Eigen::VectorXd singular = Eigen::JacobiSVD<Eigen::MatrixXd>(rows).singularValues();
  if (singular[tight - 1] < 1e-6 * singular[0]) return false;
  // M (a* − a^u) = J_Tᵀ λ_T has a unique solution; all of it must be positive.
  const Vec6 wrench = instance.mass * (exact.acceleration - instance.unconstrained);
  const Eigen::JacobiSVD<Eigen::MatrixXd> transposed(rows.transpose(),
                                                     Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd lambda = transposed.solve(wrench);
  return lambda.minCoeff() > 1e-8 * (1 + wrench.norm());
}

// ---------------------------------------------------------------------------
// KKT conditions of the solver's own answer, checked independently of it.

void check_kkt(const Instance& instance, const GaussSolution& solution) {
  const int count = static_cast<int>(instance.constraints.size());
  REQUIRE(solution.converged);
  REQUIRE(solution.multipliers.size() == instance.constraints.size());
  const double scale = 1 + instance.unconstrained.norm();
  Vec6 constraint_wrench = Vec6::Zero();
  for (int k = 0; k < count; ++k) {
    const Vec6 row = constraint_row(instance.constraints[k]);
    const double slack = row.dot(solution.acceleration) - instance.constraints[k].rhs;
    const double lambda = solution.multipliers[k];
    CHECK(slack >= -1e-12 * scale);                                   // primal feasibility
    CHECK(lambda >= 0);                                               // dual feasibility
    CHECK(std::abs(lambda * slack) <= 1e-12 * scale * (1 + lambda));  // complementarity
    constraint_wrench += lambda * row;
  }
  for (const int index : solution.active) {
    const Vec6 row = constraint_row(instance.constraints[index]);
    CHECK(std::abs(row.dot(solution.acceleration) - instance.constraints[index].rhs) <=
          1e-12 * scale);
  }
  // Stationarity: M (a − a^u) = Jᵀ λ.
  const Vec6 inertial = instance.mass * (solution.acceleration - instance.unconstrained);
  CHECK((inertial - constraint_wrench).norm() <= 1e-10 * (1 + inertial.norm()));
}

// ---------------------------------------------------------------------------
// Instance families.

// Contacts of a tool pressed against a surface: normals within 75° of the
// surface normal, contact points spread over a few centimetres of the tool.
std::vector<GaussConstraint> surface_contacts(Rng& rng, int count, const Vec3& surface_normal) {
  std::vector<GaussConstraint> constraints;
  for (int k = 0; k < count; ++k) {
    GaussConstraint c;
    c.normal = random_unit_in_cone(rng, surface_normal, 75.0 * std::numbers::pi / 180);
    c.lever = Vec3(uniform(rng, -0.03, 0.03), uniform(rng, -0.03, 0.03), uniform(rng, -0.03, 0.03));
    constraints.push_back(c);
  }
  return constraints;
}

// The four corners of a box face resting on an axis-aligned plane: the
// coordinates are multiples of 2⁻¹⁰ m, so the rows are exactly (not just
// nearly) linearly dependent in double precision, for the exact solver too.
void add_box_face(Rng& rng, std::vector<GaussConstraint>& constraints) {
  const int axis = std::uniform_int_distribution<int>(0, 2)(rng);
  const double sign = std::uniform_int_distribution<int>(0, 1)(rng) ? 1.0 : -1.0;
  const double half = std::uniform_int_distribution<int>(5, 30)(rng) / 1024.0;
  const double depth = std::uniform_int_distribution<int>(5, 30)(rng) / 1024.0;
  for (int corner = 0; corner < 4; ++corner) {
    GaussConstraint c;
    c.normal = Vec3::Zero();
    c.normal[axis] = sign;
    c.lever[axis] = -sign * depth;
    c.lever[(axis + 1) % 3] = (corner & 1) ? half : -half;
    c.lever[(axis + 2) % 3] = (corner & 2) ? half : -half;
    constraints.push_back(c);
  }
}

// Instance `index` of the 200 compared with CGAL: K = 1 + index % 24.
Instance cgal_instance(int index) {
  Rng rng(1000 + index);
  Instance instance;
  const int count = 1 + index % 24;
  const Vec3 surface_normal = random_unit(rng);
  const int family = index % 5;
  instance.mass = family == 2 ? random_general_mass(rng) : random_rigid_body_mass(rng);
  instance.unconstrained = random_unconstrained(rng, surface_normal);
  if (family == 0 || family == 1) {
    instance.constraints = surface_contacts(rng, count, surface_normal);
  } else if (family == 2) {
    // isotropic normals: with many contacts the feasible cone is often {0}
    for (int k = 0; k < count; ++k) {
      GaussConstraint c;
      c.normal = random_unit(rng);
      c.lever = 0.03 * random_unit(rng);
      instance.constraints.push_back(c);
    }
  } else if (family == 3) {
    // degenerate: a coplanar box face, then random contacts and exact duplicates
    add_box_face(rng, instance.constraints);
    instance.unconstrained.head<3>() =
        -0.8 * instance.constraints[0].normal + 0.5 * uniform(rng, 0, 1) * random_unit(rng);
    while (static_cast<int>(instance.constraints.size()) < count) {
      if (instance.constraints.size() >= 2 && uniform(rng, 0, 1) < 0.4) {
        const size_t source =
            std::uniform_int_distribution<size_t>(0, instance.constraints.size() - 1)(rng);
        instance.constraints.push_back(instance.constraints[source]);
      } else {
        const auto more = surface_contacts(rng, 1, instance.constraints[0].normal);
        instance.constraints.push_back(more[0]);
      }
    }
    instance.constraints.resize(std::max(count, 1));
  } else {
    // b ≠ 0: feasible by construction around a_f (some constraints tight at
    // a_f), every third one made infeasible by an opposing copy of a row.
    instance.rhs_nonzero = true;
    instance.constraints = surface_contacts(rng, count, surface_normal);
    Vec6 feasible;
    feasible << random_unit(rng), 10 * random_unit(rng);
    for (auto& c : instance.constraints) {
      const double slack = uniform(rng, 0, 1) < 0.3 ? 0.0 : uniform(rng, 0, 0.5);
      c.rhs = constraint_row(c).dot(feasible) - slack;
    }
    if (index % 3 == 0) {
      GaussConstraint opposing = instance.constraints[0];
      opposing.normal = -opposing.normal;
      opposing.rhs = -opposing.rhs + 0.25;  // J_0 a ≤ b_0 − 0.25 contradicts J_0 a ≥ b_0
      if (count == 1) {
        instance.constraints.push_back(opposing);
      } else {
        instance.constraints.back() = opposing;
      }
    }
  }
  return instance;
}

TEST_CASE("without constraints the unconstrained acceleration is the answer", "[gauss]") {
  Rng rng(2);
  const Mat6 mass = random_general_mass(rng);
  Vec6 unconstrained;
  unconstrained << 1, -2, 3, -4, 5, -6;
  const GaussSolution solution = solve_least_constraint(mass, unconstrained, {});
  CHECK(solution.acceleration == unconstrained);
  CHECK(solution.active.empty());
  CHECK(solution.multipliers.empty());
  CHECK(solution.iterations == 0);
  CHECK(solution.converged);
}

TEST_CASE("a contact through the centre of mass removes exactly the normal component", "[gauss]") {
  Rng rng(1);
  const Mat6 mass = random_rigid_body_mass(rng);
  GaussConstraint contact;
  contact.normal = Vec3(1, 2, 3).normalized();
  contact.lever = -0.02 * contact.normal;  // the contact point lies on the normal through the COM
  const std::vector<GaussConstraint> constraints{contact};

  SECTION("pushed into the plane") {
    Vec6 unconstrained;
    unconstrained << Vec3(0.3, -0.5, 0.1) - 2.0 * contact.normal, 1.0, -2.0, 0.5;
    const double into = unconstrained.head<3>().dot(contact.normal);
    REQUIRE(into < 0);
    const GaussSolution solution = solve_least_constraint(mass, unconstrained, constraints);
    Vec6 expected = unconstrained;
    expected.head<3>() -= into * contact.normal;
    CHECK((solution.acceleration - expected).norm() <= 1e-12);
    CHECK(solution.active == std::vector<int>{0});
    // M (a − a^u) = n λ with M's linear block m I: λ = −m (a^u · n).
    CHECK(solution.multipliers[0] == Approx(-mass(0, 0) * into).epsilon(1e-12));
    CHECK(solution.converged);
    CHECK_FALSE(solution.infeasible);
  }
  SECTION("pulled away from the plane") {
    Vec6 unconstrained;
    unconstrained << Vec3(0.3, -0.5, 0.1) + 2.0 * contact.normal, 1.0, -2.0, 0.5;
    const GaussSolution solution = solve_least_constraint(mass, unconstrained, constraints);
    CHECK(solution.acceleration == unconstrained);
    CHECK(solution.active.empty());
    CHECK(solution.multipliers == std::vector<double>{0.0});
    CHECK(solution.converged);
  }
}

// A box of half-width s resting on its four bottom corners (±s, ±s, −h) on the
// plane z = 0. Its inertia is tilted so nothing is diagonal by accident.
struct RestingBox {
  double s = 0.02;
  double h = 0.01;
  double mass_kg = 0.5;
  std::vector<GaussConstraint> corners;
  RestingBox() {
    for (int corner = 0; corner < 4; ++corner) {
      GaussConstraint c;
      c.normal = Vec3::UnitZ();
      c.lever = Vec3((corner & 1) ? s : -s, (corner & 2) ? s : -s, -h);
      corners.push_back(c);
    }
  }
};

TEST_CASE("a box on four coplanar contacts keeps its sideways motion and does not rotate",
          "[gauss]") {
  const RestingBox box;
  const Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Mat3 inertia = rotation * Vec3(2e-4, 3e-4, 4e-4).asDiagonal() * rotation.transpose();
  const Mat6 mass = rigid_body_mass_matrix(box.mass_kg, 0.5 * (inertia + inertia.transpose()));

  // Pushed down and sideways, spun about the vertical: the plane takes only
  // the downward part. (The objective separates into m|a_cm − a^u_cm|² and
  // αᵀIα, and the four corners demand a_z ≥ s(|α_x| + |α_y|), so a_z = 0,
  // α_x = α_y = 0 is optimal; α_z is unconstrained.)
  Vec6 unconstrained;
  unconstrained << 0.7, -0.4, -3.0, 0, 0, 0;
  GaussSolution solution = solve_least_constraint(mass, unconstrained, box.corners);
  Vec6 expected;
  expected << 0.7, -0.4, 0, 0, 0, 0;
  CHECK((solution.acceleration - expected).norm() <= 1e-12);
  // The four rows span three dimensions: at most three are active and the
  // multipliers hold the box: Σλ = m·3 and Σ λ (r × n) = 0.
  CHECK(solution.active.size() <= 3);
  double total = 0;
  Vec3 moment = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    CHECK(solution.multipliers[k] >= 0);
    total += solution.multipliers[k];
    moment += solution.multipliers[k] * box.corners[k].lever.cross(box.corners[k].normal);
  }
  CHECK(total == Approx(box.mass_kg * 3.0).epsilon(1e-12));
  CHECK(moment.norm() <= 1e-12);

  SECTION("a spin about the normal is kept") {
    unconstrained << 0.7, -0.4, -3.0, 0, 0, 5.0;
    solution = solve_least_constraint(mass, unconstrained, box.corners);
    // With a tilted inertia α couples to nothing in the constraints but α_z;
    // the solution keeps a_cm as above and minimises (α − α^u)ᵀI(α − α^u)
    // over α_x = α_y = 0: α_z = α^u_z + (I_zx α^u_x + I_zy α^u_y)/I_zz = 5.
    expected << 0.7, -0.4, 0, 0, 0, 5.0;
    CHECK((solution.acceleration - expected).norm() <= 1e-12);
  }
}

TEST_CASE("a box tipped about one edge pivots on it with the edge's moment of inertia", "[gauss]") {
  // Diagonal inertia, a^u = pure roll α_x = ω. The corners at y = −s would
  // sink; with a_z = s α_x they stay on the plane, and minimising
  // m a_z² + I_x (α_x − ω)² gives α_x = I_x ω / (I_x + m s²): rotation about
  // the edge with the parallel-axis inertia.
  const RestingBox box;
  const Vec3 principal(2e-4, 3e-4, 4e-4);
  const Mat6 mass = rigid_body_mass_matrix(box.mass_kg, principal.asDiagonal());
  const double omega = 4.0;
  Vec6 unconstrained;
  unconstrained << 0, 0, 0, omega, 0, 0;
  const GaussSolution solution = solve_least_constraint(mass, unconstrained, box.corners);
  const double alpha = principal.x() * omega / (principal.x() + box.mass_kg * box.s * box.s);
  Vec6 expected;
  expected << 0, 0, box.s * alpha, alpha, 0, 0;
  CHECK((solution.acceleration - expected).norm() <= 1e-12);
  CHECK(solution.active == std::vector<int>{0, 1});  // corners 0 and 1 have y = −s
  CHECK(solution.multipliers[0] == Approx(0.5 * box.mass_kg * box.s * alpha).epsilon(1e-12));
  CHECK(solution.multipliers[1] == Approx(0.5 * box.mass_kg * box.s * alpha).epsilon(1e-12));
  CHECK(solution.multipliers[2] == 0);
  CHECK(solution.multipliers[3] == 0);
}

TEST_CASE("a cube wedged into a corner by twelve contacts", "[gauss]") {
  // Floor z, walls x and y, four corner contacts each: 12 rows of rank 6.
  const double s = 0.015;
  std::vector<GaussConstraint> constraints;
  for (int axis = 0; axis < 3; ++axis) {
    for (int corner = 0; corner < 4; ++corner) {
      GaussConstraint c;
      c.normal = Vec3::Unit(axis);
      c.lever[axis] = -s;
      c.lever[(axis + 1) % 3] = (corner & 1) ? s : -s;
      c.lever[(axis + 2) % 3] = (corner & 2) ? s : -s;
      constraints.push_back(c);
    }
  }
  const double m = 0.3;
  const Mat6 mass = rigid_body_mass_matrix(m, Vec3(1e-5, 1.2e-5, 0.9e-5).asDiagonal());
  // Each wall demands a_i ≥ s(|α_j| + |α_k|) for the other two axes, so
  // pushing into all three walls leaves a = 0, and pulling away from one
  // (here the floor) keeps that component: a = (0, 0, a^u_z).
  Vec6 unconstrained;
  unconstrained << -1.0, -2.0, -0.5, 3.0, -1.0, 2.0;
  GaussSolution solution = solve_least_constraint(mass, unconstrained, constraints);
  CHECK(solution.acceleration.norm() <= 1e-12);
  CHECK(solution.active.size() <= 6);
  // The walls hold the cube: Σ λ J_kᵀ = −M a^u, force per wall and moment.
  Vec3 moment = Vec3::Zero();
  for (int k = 0; k < 12; ++k) {
    moment += solution.multipliers[k] * constraints[k].lever.cross(constraints[k].normal);
  }
  const Vec3 inertial_moment = mass.bottomRightCorner<3, 3>() * unconstrained.tail<3>();
  CHECK((moment + inertial_moment).norm() <= 1e-10 * inertial_moment.norm());
  for (int axis = 0; axis < 3; ++axis) {
    double wall_force = 0;
    for (int corner = 0; corner < 4; ++corner)
      wall_force += solution.multipliers[4 * axis + corner];
    CHECK(wall_force == Approx(-m * unconstrained[axis]).epsilon(1e-10));
  }
  unconstrained << -1.0, -2.0, 0.5, 0, 0, 0;
  solution = solve_least_constraint(mass, unconstrained, constraints);
  Vec6 expected;
  expected << 0, 0, 0.5, 0, 0, 0;
  CHECK((solution.acceleration - expected).norm() <= 1e-12);
}

TEST_CASE("constraints with a right-hand side", "[gauss]") {
  const Mat6 mass = rigid_body_mass_matrix(1.5, Vec3(1e-3, 2e-3, 3e-3).asDiagonal());
  GaussConstraint up;
  up.normal = Vec3::UnitZ();
  up.rhs = 1.0;  // the contact point must accelerate upwards at ≥ 1 m/s²
  SECTION("feasible: a lower bound on the normal acceleration") {
    const std::vector<GaussConstraint> constraints{up};
    const GaussSolution solution = solve_least_constraint(mass, Vec6::Zero(), constraints);
    Vec6 expected = Vec6::Zero();
    expected[2] = 1.0;
    CHECK((solution.acceleration - expected).norm() <= 1e-12);
    CHECK(solution.multipliers[0] == Approx(1.5).epsilon(1e-12));
    CHECK(solution.converged);
    CHECK_FALSE(solution.infeasible);
  }
  SECTION("infeasible: two opposing contacts that both demand separation") {
    GaussConstraint down = up;
    down.normal = -Vec3::UnitZ();
    const std::vector<GaussConstraint> constraints{up, down};
    const GaussSolution solution = solve_least_constraint(mass, Vec6::Zero(), constraints);
    CHECK(solution.infeasible);
    CHECK_FALSE(solution.converged);
  }
}

TEST_CASE("bad input names what is wrong", "[gauss]") {
  const Mat6 mass = rigid_body_mass_matrix(1.0, Mat3::Identity() * 1e-3);
  GaussConstraint contact;
  std::vector<GaussConstraint> constraints{contact};
  SECTION("a normal that is not unit length") {
    constraints[0].normal = Vec3(0, 0, 2);
    CHECK_THROWS_WITH(solve_least_constraint(mass, Vec6::Zero(), constraints),
                      Catch::Contains("constraints[0].normal") && Catch::Contains("unit"));
  }
  SECTION("a non-finite lever") {
    constraints[0].lever = Vec3(0, std::nan(""), 0);
    CHECK_THROWS_WITH(solve_least_constraint(mass, Vec6::Zero(), constraints),
                      Catch::Contains("constraints[0].lever"));
  }
  SECTION("a mass matrix that is not positive definite") {
    Mat6 singular = mass;
    singular(5, 5) = -1e-3;
    CHECK_THROWS_AS(solve_least_constraint(singular, Vec6::Zero(), constraints), InputError);
  }
  SECTION("a non-symmetric mass matrix") {
    Mat6 skewed = mass;
    skewed(0, 5) = 0.1;
    CHECK_THROWS_WITH(solve_least_constraint(skewed, Vec6::Zero(), constraints),
                      Catch::Contains("symmetric"));
  }
  SECTION("a warm-start index out of range") {
    const std::vector<int> warm{0, 3};
    CHECK_THROWS_WITH(solve_least_constraint(mass, Vec6::Zero(), constraints, warm),
                      Catch::Contains("warm_active[1]"));
  }
}

TEST_CASE("KKT conditions hold on random instances, degenerate ones included", "[gauss]") {
  GaussLeastConstraintSolver solver;
  for (int index = 0; index < 400; ++index) {
    Rng rng(77 + index);
    Instance instance;
    const int count = 1 + index % 64;
    const Vec3 surface_normal = random_unit(rng);
    instance.mass = index % 3 == 0 ? random_general_mass(rng) : random_rigid_body_mass(rng);
    instance.unconstrained = random_unconstrained(rng, surface_normal);
    instance.constraints = surface_contacts(rng, count, surface_normal);
    if (index % 4 == 1) add_box_face(rng, instance.constraints);
    if (index % 4 == 2) {
      const size_t copies = instance.constraints.size();
      for (size_t k = 0; k < copies; k += 2)
        instance.constraints.push_back(instance.constraints[k]);
    }
    if (index % 4 == 3) {  // isotropic normals: often only a = 0 is feasible
      for (auto& c : instance.constraints) c.normal = random_unit(rng);
    }
    INFO("instance " << index << ", " << instance.constraints.size() << " constraints");
    const GaussSolution& solution =
        solver.solve(instance.mass, instance.unconstrained, instance.constraints);
    check_kkt(instance, solution);
    CHECK(solution.active.size() <= 6);
  }
}

TEST_CASE("warm starts reach the same solution from good and bad guesses", "[gauss]") {
  GaussLeastConstraintSolver solver;
  int fewer_iterations = 0;
  for (int index = 0; index < 100; ++index) {
    Rng rng(5000 + index);
    const int count = 4 + index % 40;
    const Vec3 surface_normal = random_unit(rng);
    const Mat6 mass = random_rigid_body_mass(rng);
    const Vec6 unconstrained = random_unconstrained(rng, surface_normal);
    std::vector<GaussConstraint> constraints = surface_contacts(rng, count, surface_normal);
    if (index % 2) add_box_face(rng, constraints);
    const GaussSolution cold = solver.solve(mass, unconstrained, constraints);
    REQUIRE(cold.converged);
    const std::vector<int> good = cold.active;

    // The previous tick's active set on a slightly different problem.
    const Vec6 nudged = unconstrained + 0.01 * Vec6::Ones();
    const GaussSolution nudged_cold = solver.solve(mass, nudged, constraints);
    const GaussSolution nudged_warm = solver.solve(mass, nudged, constraints, good);
    CHECK((nudged_warm.acceleration - nudged_cold.acceleration).norm() <=
          1e-10 * (1 + nudged_cold.acceleration.norm()));
    if (nudged_warm.iterations < nudged_cold.iterations) ++fewer_iterations;

    std::vector<int> everything(constraints.size());
    for (size_t k = 0; k < everything.size(); ++k) everything[k] = static_cast<int>(k);
    std::shuffle(everything.begin(), everything.end(), rng);
    const GaussSolution bad = solver.solve(mass, unconstrained, constraints, everything);
    REQUIRE(bad.converged);
    CHECK((bad.acceleration - cold.acceleration).norm() <= 1e-10 * (1 + cold.acceleration.norm()));
    Instance instance{mass, unconstrained, constraints};
    check_kkt(instance, bad);

    const GaussSolution exact_guess = solver.solve(mass, unconstrained, constraints, good);
    CHECK(exact_guess.iterations == 0);
    CHECK(exact_guess.active == good);
  }
  // Most of the time the previous active set is still right after a small change.
  CHECK(fewer_iterations >= 50);
}

TEST_CASE("agrees with CGAL's exact QP solver on 200 random instances", "[gauss][cgal]") {
  int feasible = 0, objective_agreements = 0;
  int infeasible = 0, infeasible_agreements = 0;
  int nondegenerate = 0, active_set_agreements = 0;
  GaussLeastConstraintSolver solver;
  for (int index = 0; index < 200; ++index) {
    const Instance instance = cgal_instance(index);
    INFO("instance " << index << ", " << instance.constraints.size() << " constraints");
    const ExactSolution exact = solve_exactly(instance);
    const GaussSolution& solution =
        solver.solve(instance.mass, instance.unconstrained, instance.constraints);
    if (exact.infeasible) {
      ++infeasible;
      CHECK(solution.infeasible);
      if (solution.infeasible) ++infeasible_agreements;
      continue;
    }
    ++feasible;
    REQUIRE(solution.converged);
    check_kkt(instance, solution);
    const double unconstrained_objective = objective(instance, Vec6::Zero());
    const double mine = objective(instance, solution.acceleration);
    const bool objective_agrees = std::abs(mine - exact.objective) <=
                                  1e-9 * exact.objective + 1e-15 * unconstrained_objective;
    CHECK(objective_agrees);
    if (objective_agrees) ++objective_agreements;
    CHECK((solution.acceleration - exact.acceleration).norm() <=
          1e-7 * (1 + exact.acceleration.norm()));
    if (is_nondegenerate(instance, exact)) {
      ++nondegenerate;
      CHECK(solution.active == exact.tight);
      if (solution.active == exact.tight) ++active_set_agreements;
    } else {
      // Degenerate: every constraint the solver holds active is tight at the
      // exact optimum up to rounding (its multiplier set is one of many).
      const double scale = 1 + exact.acceleration.norm() + instance.unconstrained.norm();
      for (const int index_active : solution.active) {
        CHECK(std::abs(exact.slack[index_active]) <= 1e-9 * scale);
      }
    }
  }
  INFO("feasible " << feasible << ", infeasible " << infeasible << ", non-degenerate "
                   << nondegenerate);
  CHECK(objective_agreements == feasible);
  CHECK(infeasible_agreements == infeasible);
  CHECK(active_set_agreements == nondegenerate);
  // The families are built so that each kind of comparison really happens.
  CHECK(nondegenerate >= 80);
  CHECK(feasible - nondegenerate >= 30);
  CHECK(infeasible >= 10);
}

}  // namespace
}  // namespace hb
