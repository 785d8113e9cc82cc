#include "harness/reference/rigid_proxy_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

#include "hapticbench/closest_points.h"
#include "harness/reference/surface_samples.h"

namespace hb {

namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

// Lawson–Hanson non-negative least squares: u ≥ 0 minimising |E u − f|.
// E has few rows (7) and any number of columns; the passive set never
// holds more columns than the rank allows.
VecX non_negative_least_squares(const MatX& e, const VecX& f) {
  const Eigen::Index m = e.cols();
  VecX u = VecX::Zero(m);
  std::vector<uint8_t> passive(static_cast<std::size_t>(m), 0);
  const double scale = std::max(1.0, e.cwiseAbs().maxCoeff()) * std::max(1.0, f.norm());
  const double tolerance = 1e-13 * scale;
  std::vector<Eigen::Index> columns;
  VecX z;
  const auto solve_passive = [&] {
    columns.clear();
    for (Eigen::Index j = 0; j < m; ++j)
      if (passive[static_cast<std::size_t>(j)]) columns.push_back(j);
    MatX ep(e.rows(), static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < columns.size(); ++k)
      ep.col(static_cast<Eigen::Index>(k)) = e.col(columns[k]);
    const VecX zp = ep.completeOrthogonalDecomposition().solve(f);
    z = VecX::Zero(m);
    for (std::size_t k = 0; k < columns.size(); ++k)
      z[columns[k]] = zp[static_cast<Eigen::Index>(k)];
  };
  for (Eigen::Index outer = 0; outer < 3 * m + 10; ++outer) {
    const VecX w = e.transpose() * (f - e * u);
    Eigen::Index best = -1;
    double best_w = tolerance;
    for (Eigen::Index j = 0; j < m; ++j)
      if (!passive[static_cast<std::size_t>(j)] && w[j] > best_w) best_w = w[j], best = j;
    if (best < 0) break;
    passive[static_cast<std::size_t>(best)] = 1;
    for (int inner = 0; inner < 100; ++inner) {
      solve_passive();
      bool positive = true;
      for (Eigen::Index j : columns) positive = positive && z[j] > 0;
      if (positive) {
        u = z;
        break;
      }
      double alpha = 1.0;
      for (Eigen::Index j : columns)
        if (z[j] <= 0) alpha = std::min(alpha, u[j] / (u[j] - z[j]));
      u += alpha * (z - u);
      for (Eigen::Index j : columns)
        if (u[j] <= tolerance * 1e-3) u[j] = 0, passive[static_cast<std::size_t>(j)] = 0;
    }
  }
  return u;
}

// The mesh's sharp edges (faces meeting at more than kSharpDegrees, or an
// open boundary) as pairs of vertex indices.
constexpr double kSharpDegrees = 5.0;

std::vector<std::array<int, 2>> sharp_edges(const TriangleMesh& mesh) {
  std::vector<std::array<int, 3>> edges;  // (low vertex, high vertex, triangle)
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t)});
    }
  std::sort(edges.begin(), edges.end());
  const auto normal = [&](int t) {
    const auto& [a, b, c] = mesh.triangles[static_cast<std::size_t>(t)];
    return (mesh.vertices[b] - mesh.vertices[a])
        .cross(mesh.vertices[c] - mesh.vertices[a])
        .normalized();
  };
  const double sharp_cos = std::cos(kSharpDegrees * M_PI / 180.0);
  std::vector<std::array<int, 2>> sharp;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    if (j - i != 2 || normal(edges[i][2]).dot(normal(edges[i + 1][2])) < sharp_cos)
      sharp.push_back({edges[i][0], edges[i][1]});
    i = j;
  }
  return sharp;
}

// The points dividing the edge [a, b] into pieces no longer than `spacing`
// (m), from a to b, both included.
std::vector<Vec3> edge_division(const Vec3& a, const Vec3& b, double spacing) {
  const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
  std::vector<Vec3> points;
  for (int k = 0; k <= pieces; ++k) points.push_back(a + (b - a) * (double(k) / pieces));
  return points;
}

// Points along the mesh's sharp edges, about `spacing` apart, endpoints
// excluded: with the vertices they keep a scene's ridges out of the tool
// between its own samples.
void add_sharp_edge_points(const TriangleMesh& mesh, const Pose& pose, double spacing,
                           std::vector<Vec3>& out) {
  for (const auto& [a, b] : sharp_edges(mesh)) {
    const std::vector<Vec3> points =
        edge_division(pose.transform_point(mesh.vertices[static_cast<std::size_t>(a)]),
                      pose.transform_point(mesh.vertices[static_cast<std::size_t>(b)]), spacing);
    out.insert(out.end(), points.begin() + 1, points.end() - 1);
  }
}

// Closest points of the segment [a, b] (on_p) and the triangle (on_q), m,
// one frame: the nearest of its endpoints against the triangle, the
// segment against the triangle's edges, and the point where it crosses the
// triangle's plane (distance 0 where that point is inside).
SegmentClosestPoints closest_points_of_segment_and_triangle(const Vec3& a, const Vec3& b,
                                                            const std::array<Vec3, 3>& t) {
  const auto on_triangle = [&](const Vec3& p) {
    return closest_point_on_triangle(p, t[0], t[1], t[2]);
  };
  SegmentClosestPoints best{a, on_triangle(a)};
  const auto consider = [&](const Vec3& p, const Vec3& q) {
    if ((p - q).squaredNorm() < (best.on_p - best.on_q).squaredNorm()) best = {p, q};
  };
  consider(b, on_triangle(b));
  for (int k = 0; k < 3; ++k) {
    const SegmentClosestPoints edge = closest_points_of_segments(a, b, t[k], t[(k + 1) % 3]);
    consider(edge.on_p, edge.on_q);
  }
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double da = n.dot(a - t[0]), db = n.dot(b - t[0]);
  if ((da < 0) != (db < 0)) {
    const Vec3 crossing = a + (b - a) * (da / (da - db));
    consider(crossing, on_triangle(crossing));
  }
  return best;
}

// Sets distance[indices[k]] to the exact distance of points[k] from the
// oracle's surface.
void refresh_distances(const Oracle& oracle, std::span<const Vec3> points,
                       std::span<const std::size_t> indices, std::vector<double>& distance) {
  if (points.empty()) return;
  PointQueryRequest request;
  request.points = points;
  request.want_inside = false;
  request.want_closest = true;
  PointQueryResult result;
  oracle.query_points(request, result);
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (result.distance[k] >= 0) distance[indices[k]] = result.distance[k];
}

}  // namespace

/// n·(δx + φ × r) ≥ b, written as a·δ ≥ b with a = (n, r × n).
struct RigidProxyReference::Row {
  Vec3 point = Vec3::Zero();  ///< m, world: where the contact acts (on the scene side)
  Vec6 a;
  double b = 0;         ///< m: ε − d
  double distance = 0;  ///< m: d
  double friction = 0;  ///< Coulomb μ of the scene object in this contact
};

RigidProxyReference::RigidProxyReference(const std::vector<SceneObject>& scene,
                                         const TriangleMesh& tool_mesh, const CouplingGains& gains,
                                         const RigidProxySettings& settings)
    : settings_(settings), gains_(gains) {
  scene_ = make_embree_oracle(scene);
  SceneObject tool;
  tool.name = "tool";
  tool.mesh = tool_mesh;
  tool.distance_only = true;  // distances to its surface only
  tool_ = make_embree_oracle({tool});

  spacing_m_ = settings_.sample_spacing_m > 0 ? settings_.sample_spacing_m
                                              : tool_mesh.bounds().diagonal().norm() / 40.0;
  // Every vertex (the deepest point of a polyhedral tool on a face is
  // one), then the samples between them.
  tool_samples_ = tool_mesh.vertices;
  const std::vector<Vec3> samples = sample_surface(tool_mesh, spacing_m_);
  tool_samples_.insert(tool_samples_.end(), samples.begin(), samples.end());
  for (const Vec3& s : tool_samples_) tool_radius_m_ = std::max(tool_radius_m_, s.norm());
  for (const Vec3& v : tool_mesh.vertices) tool_radius_m_ = std::max(tool_radius_m_, v.norm());
  sample_distance_.assign(tool_samples_.size(), -1.0);
  sample_motion_at_.assign(tool_samples_.size(), 0.0);
  for (const auto& [a, b] : sharp_edges(tool_mesh)) {
    const std::vector<Vec3> points =
        edge_division(tool_mesh.vertices[static_cast<std::size_t>(a)],
                      tool_mesh.vertices[static_cast<std::size_t>(b)], spacing_m_);
    for (std::size_t k = 0; k + 1 < points.size(); ++k)
      tool_edge_pieces_.push_back({points[k], points[k + 1]});
  }
  edge_distance_.assign(tool_edge_pieces_.size(), -1.0);
  edge_motion_at_.assign(tool_edge_pieces_.size(), 0.0);

  for (const SceneObject& object : scene) {
    for (const Vec3& v : object.mesh.vertices)
      scene_vertices_.push_back(object.pose.transform_point(v));
    add_sharp_edge_points(object.mesh, object.pose, spacing_m_, scene_vertices_);
    const double mu = settings_.friction ? object.friction : 0.0;
    object_friction_.push_back(mu);
    scene_vertex_friction_.resize(scene_vertices_.size(), mu);
  }
  vertex_distance_.assign(scene_vertices_.size(), -1.0);
  vertex_motion_at_.assign(scene_vertices_.size(), 0.0);
  cell_m_ = std::max(tool_radius_m_, 1e-4);
  vertex_cells_.reserve(scene_vertices_.size());
  for (std::size_t i = 0; i < scene_vertices_.size(); ++i) {
    const Vec3 c = (scene_vertices_[i] / cell_m_).array().floor();
    const int64_t key = (static_cast<int64_t>(c.x()) * 73856093) ^
                        (static_cast<int64_t>(c.y()) * 19349663) ^
                        (static_cast<int64_t>(c.z()) * 83492791);
    vertex_cells_.push_back({key, static_cast<int32_t>(i)});
  }
  std::sort(vertex_cells_.begin(), vertex_cells_.end());
}

RigidProxyReference::~RigidProxyReference() = default;

// One linearised distance: `out` the unit direction from the scene's point
// to the tool's, `point` the contact's point (on the scene side).
void RigidProxyReference::add_row(const Vec3& out, const Vec3& point, double distance, double mu) {
  Row row;
  row.point = point;
  row.a.head<3>() = out;
  row.a.tail<3>() = (point - proxy_->p).cross(out);
  row.b = settings_.clearance_m - distance;
  row.distance = distance;
  row.friction = mu;
  rows_.push_back(row);
}

double RigidProxyReference::friction_of(int32_t object) const {
  return object >= 0 ? object_friction_[static_cast<std::size_t>(object)] : 0.0;
}

// The tool's sharp edges, piece by piece, against every scene triangle
// within the band, by exact segment–triangle distances: a tool ridge
// crossing a scene ridge between their samples keeps ε too (the samples
// alone let it sink up to half their spacing). Lower bounds are kept per
// piece as for the samples.
void RigidProxyReference::collect_edge_rows(double band) {
  const Pose& pose = *proxy_;
  std::vector<std::size_t> far_pieces;
  std::vector<Vec3> far_middles;
  for (std::size_t i = 0; i < tool_edge_pieces_.size(); ++i) {
    if (edge_distance_[i] - (motion_m_ - edge_motion_at_[i]) >= band) continue;
    const Vec3 a = pose.transform_point(tool_edge_pieces_[i][0]);
    const Vec3 b = pose.transform_point(tool_edge_pieces_[i][1]);
    const Vec3 middle = 0.5 * (a + b);
    scene_->triangles_within(middle, band + 0.5 * (b - a).norm(), near_);
    ++stats_.point_queries;
    double least = band;
    for (const NearTriangle& t : near_) {
      const SegmentClosestPoints closest = closest_points_of_segment_and_triangle(a, b, t.corners);
      const double distance = closest.distance();
      if (distance >= band) continue;
      least = std::min(least, distance);
      if (distance > 0)
        add_row((closest.on_p - closest.on_q) / distance, closest.on_q, distance,
                friction_of(t.object));
    }
    edge_distance_[i] = least;
    edge_motion_at_[i] = motion_m_;
    if (near_.empty()) far_pieces.push_back(i), far_middles.push_back(middle);
  }
  // A piece is no nearer than its middle less half its length.
  refresh_distances(*scene_, far_middles, far_pieces, edge_distance_);
  for (std::size_t i : far_pieces)
    edge_distance_[i] -= 0.5 * (tool_edge_pieces_[i][1] - tool_edge_pieces_[i][0]).norm();
}

// Every linearised distance the next step can change by more than its
// clearance: samples, tool edge pieces and scene vertices whose distance's lower bound is
// below `band`, against every triangle within the band.
void RigidProxyReference::collect_rows(double band) {
  rows_.clear();
  const Pose& pose = *proxy_;
  // Points with nothing within the band get their exact distance as their
  // bound (one batch per side), so they are not asked again for a while.
  std::vector<std::size_t> far_samples, far_vertices;
  std::vector<Vec3> far_points;
  for (std::size_t i = 0; i < tool_samples_.size(); ++i) {
    if (sample_distance_[i] - (motion_m_ - sample_motion_at_[i]) >= band) continue;
    const Vec3 p = pose.transform_point(tool_samples_[i]);
    scene_->triangles_within(p, band, near_);
    ++stats_.point_queries;
    double least = band;
    for (const NearTriangle& t : near_) {
      least = std::min(least, t.distance);
      if (t.distance > 0)
        add_row((p - t.closest) / t.distance, t.closest, t.distance, friction_of(t.object));
    }
    sample_distance_[i] = least;
    sample_motion_at_[i] = motion_m_;
    if (near_.empty()) far_samples.push_back(i), far_points.push_back(p);
  }
  refresh_distances(*scene_, far_points, far_samples, sample_distance_);
  collect_edge_rows(band);
  // Scene vertices in the cells the tool's sphere (grown by the band) touches.
  const double reach = tool_radius_m_ + band;
  const Vec3 low = ((pose.p.array() - reach) / cell_m_).floor();
  const Vec3 high = ((pose.p.array() + reach) / cell_m_).floor();
  for (int64_t x = static_cast<int64_t>(low.x()); x <= static_cast<int64_t>(high.x()); ++x)
    for (int64_t y = static_cast<int64_t>(low.y()); y <= static_cast<int64_t>(high.y()); ++y)
      for (int64_t z = static_cast<int64_t>(low.z()); z <= static_cast<int64_t>(high.z()); ++z) {
        const int64_t key = (x * 73856093) ^ (y * 19349663) ^ (z * 83492791);
        auto it = std::lower_bound(vertex_cells_.begin(), vertex_cells_.end(),
                                   std::pair<int64_t, int32_t>(key, -1));
        for (; it != vertex_cells_.end() && it->first == key; ++it) {
          const auto j = static_cast<std::size_t>(it->second);
          const Vec3& v = scene_vertices_[j];
          if ((v - pose.p).norm() > reach) continue;
          if (vertex_distance_[j] - (motion_m_ - vertex_motion_at_[j]) >= band) continue;
          tool_->triangles_within(pose.inverse_transform_point(v), band, near_);
          ++stats_.point_queries;
          double least = band;
          for (const NearTriangle& t : near_) {
            least = std::min(least, t.distance);
            const Vec3 closest = pose.transform_point(t.closest);
            if (t.distance > 0)
              add_row((closest - v) / t.distance, closest, t.distance, scene_vertex_friction_[j]);
          }
          vertex_distance_[j] = least;
          vertex_motion_at_[j] = motion_m_;
          if (near_.empty()) far_vertices.push_back(j);
        }
      }
  far_points.clear();
  for (std::size_t j : far_vertices)
    far_points.push_back(pose.inverse_transform_point(scene_vertices_[j]));
  refresh_distances(*tool_, far_points, far_vertices, vertex_distance_);
}

// The step δ = (δx, φ) minimising ½(δ − g)ᵀK(δ − g) subject to every row:
// with z = S(δ − g), S = K^½, a least-distance program min |z| subject to
// (a S⁻¹) z ≥ b − a·g, solved by NNLS (Lawson and Hanson, ch. 23).
bool RigidProxyReference::solve_step(const Vec3& gx, const Vec3& gphi, Vec6& step) const {
  Vec6 g;
  g << gx, gphi;
  Vec6 s_inverse;
  s_inverse << Vec3::Constant(1 / std::sqrt(gains_.k_t)), Vec3::Constant(1 / std::sqrt(gains_.k_r));
  const auto m = static_cast<Eigen::Index>(rows_.size());
  bool binding = false;
  for (const Row& row : rows_) binding = binding || row.a.dot(g) < row.b;
  if (!binding) {
    step = g;
    return true;
  }
  MatX e(7, m);
  VecX f = VecX::Zero(7);
  f[6] = 1;
  for (Eigen::Index j = 0; j < m; ++j) {
    const Row& row = rows_[static_cast<std::size_t>(j)];
    e.col(j).head<6>() = row.a.cwiseProduct(s_inverse);
    e(6, j) = row.b - row.a.dot(g);
  }
  const VecX u = non_negative_least_squares(e, f);
  const VecX r = e * u - f;
  if (!(std::abs(r[6]) > 1e-12)) return false;  // no step satisfies every row
  const Vec6 z = -r.head<6>() / r[6];
  step = g + z.cwiseProduct(s_inverse);
  return true;
}

RigidProxyReference::Balance RigidProxyReference::balance(const Vec3& gx, const Vec3& gphi) const {
  Balance out;
  for (const Row& row : rows_)
    if (row.distance <= 10 * settings_.clearance_m) out.rows.push_back(&row);
  Vec6 pull;  // S g: the coupling's pull in the energy metric
  pull << std::sqrt(gains_.k_t) * gx, std::sqrt(gains_.k_r) * gphi;
  if (!(pull.norm() > 0)) {
    out.normal_force.assign(out.rows.size(), 0.0);
    return out;
  }
  if (out.rows.empty()) {
    out.residual = 1;
    return out;
  }
  MatX e(6, static_cast<Eigen::Index>(out.rows.size()));
  for (std::size_t j = 0; j < out.rows.size(); ++j) {
    const Vec6& a = out.rows[j]->a;
    e.col(static_cast<Eigen::Index>(j)) << a.head<3>() / std::sqrt(gains_.k_t),
        a.tail<3>() / std::sqrt(gains_.k_r);
  }
  // Contact forces Aᵀλ balance the pull K g: in the metric, E λ = −S g.
  const VecX f = -pull;
  const VecX lambda = non_negative_least_squares(e, f);
  out.residual = (e * lambda - f).norm() / pull.norm();
  out.normal_force.assign(lambda.data(), lambda.data() + lambda.size());
  return out;
}

void RigidProxyReference::apply_friction(const Balance& contacts, const Pose& device,
                                         IdealRendering& rendering) {
  double limit_n = 0;  // Σ μ_i λ_i
  for (std::size_t j = 0; j < contacts.rows.size(); ++j)
    limit_n += contacts.rows[j]->friction * contacts.normal_force[j];
  const Vec3 force = rendering.display.force;
  if (!rendering.in_contact || !(limit_n > 0) || !(force.norm() > 0)) {
    friction_proxy_p_.reset();
    return;
  }
  stats_.friction_limit_n = limit_n;
  const Vec3 n = force.normalized();
  Vec3 offset = Vec3::Zero();  // m, ⟂ n: the frictional proxy relative to the frictionless one
  if (friction_proxy_p_) {
    const Vec3 kept = *friction_proxy_p_ - rendering.proxy.p;
    offset = kept - n.dot(kept) * n;
  }
  const double limit_m = limit_n / gains_.k_t;
  const double length = offset.norm();
  stats_.sticking = length <= limit_m;
  if (!stats_.sticking) offset *= limit_m / length;
  // The friction's moment about the tool origin: the friction force acts
  // at the contacts, taken at their load-weighted centroid (exact for one
  // contact point, a sphere's; on a face the split of the load between
  // redundant rows is arbitrary, and with it the twisting part). The proxy
  // turns so that its rotational coupling balances it.
  Vec3 centroid = Vec3::Zero();
  double load = 0;
  for (std::size_t j = 0; j < contacts.rows.size(); ++j) {
    centroid += contacts.normal_force[j] * contacts.rows[j]->point;
    load += contacts.normal_force[j];
  }
  const Vec3 lever = load > 0 ? Vec3(centroid / load - rendering.proxy.p) : Vec3::Zero();
  const Vec3 moment = lever.cross(gains_.k_t * offset);
  rendering.proxy.p += offset;
  rendering.display.force = gains_.k_t * (rendering.proxy.p - device.p);
  rendering.display.torque += moment;
  if (gains_.k_r > 0)
    rendering.proxy.q =
        (quat_from_rotation_vector(moment / gains_.k_r) * rendering.proxy.q).normalized();
  friction_proxy_p_ = rendering.proxy.p;
}

bool RigidProxyReference::start_at(const Pose& device) {
  const auto clear = [&](const PointQueryResult& found, std::size_t i) {
    return !found.inside[i] && found.distance[i] >= settings_.clearance_m;
  };
  // The point that blocked the last start, alone first: a tool that stays
  // inside the scene costs one point a tick, not the whole sampling (a
  // tool started inside a mesh once cost 11 ms a tick).
  if (blocking_sample_ < tool_samples_.size()) {
    const Vec3 point = device.transform_point(tool_samples_[blocking_sample_]);
    PointQueryRequest one;
    one.points = std::span<const Vec3>(&point, 1);
    one.want_inside = true;
    one.want_closest = true;
    PointQueryResult found_one;
    scene_->query_points(one, found_one);
    if (!clear(found_one, 0)) return false;
  }
  std::vector<Vec3> points(tool_samples_.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = device.transform_point(tool_samples_[i]);
  // One query: every point outside the scene and at least ε from it.
  PointQueryRequest request;
  request.points = points;
  request.want_inside = true;
  request.want_closest = true;
  PointQueryResult found;
  scene_->query_points(request, found);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!clear(found, i)) {
      blocking_sample_ = i;
      return false;
    }
  proxy_ = device;
  return true;
}

std::optional<IdealRendering> RigidProxyReference::update(const Pose& device) {
  stats_ = RigidProxyUpdateStats{};
  if (!proxy_ && !start_at(device)) return std::nullopt;
  Pose& pose = *proxy_;
  const double eps = settings_.clearance_m;
  const double rotation_limit = std::sqrt(eps / std::max(tool_radius_m_, 1e-9));
  Vec3 gx, gphi;
  for (;;) {
    gx = device.p - pose.p;
    gphi = rotation_vector(device.q * pose.q.conjugate());
    const double full = gx.norm() + gphi.norm() * tool_radius_m_;
    if (full <= settings_.step_tolerance_m) {
      rows_.clear();
      stats_.converged = true;
      break;
    }
    if (stats_.iterations >= settings_.max_iterations) break;
    ++stats_.iterations;
    // The band follows the steps taken: wide enough for the last one twice
    // over, four times wider after a step it cut short. Steps in contact
    // are short, and a narrow band linearises few triangles.
    const double band =
        std::clamp(std::min(full, band_hint_m_), 4 * eps, settings_.band_max_m) + eps;
    collect_rows(band);
    stats_.constraints = static_cast<int>(rows_.size());
    Vec6 step;
    if (!solve_step(gx, gphi, step)) {
      stats_.infeasible = true;
      break;
    }
    const Vec3 dx = step.head<3>();
    const Vec3 phi = step.tail<3>();
    const double moves = dx.norm() + phi.norm() * tool_radius_m_;
    if (moves <= settings_.step_tolerance_m) {
      stats_.converged = true;
      break;
    }
    double scale = std::min(1.0, (band - eps) / moves);
    band_hint_m_ = scale < 1 ? 4 * band : 2 * moves;
    if (!rows_.empty() && phi.norm() > rotation_limit)
      scale = std::min(scale, rotation_limit / phi.norm());
    pose.p += scale * dx;
    pose.q = (quat_from_rotation_vector(scale * phi) * pose.q).normalized();
    motion_m_ += scale * moves;
  }
  const Balance contacts = balance(gx, gphi);
  stats_.kkt_residual = rows_.empty() ? 0.0 : contacts.residual;

  IdealRendering rendering;
  rendering.proxy = pose;
  rendering.display.force = gains_.k_t * (pose.p - device.p);
  rendering.display.torque = -gains_.k_r * rotation_vector(device.q * pose.q.conjugate());
  for (const Row& row : rows_)
    rendering.in_contact = rendering.in_contact || row.distance <= 10 * eps;
  if (rendering.in_contact && rendering.display.force.norm() > 0)
    rendering.contact_normal = rendering.display.force.normalized();
  apply_friction(contacts, device, rendering);
  return rendering;
}

}  // namespace hb
