#include "registration/ndt_objective.h"

#include <algorithm>
#include <cmath>

#include "registration/pose_increment.h"

namespace ndtom::registration {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Terms with d2·s/2 above this add less than exp(−20) ≈ 2e-9 of a full match: skipped.
constexpr double kMaxExponent = 20.0;
constexpr double kMatchedSquaredMahalanobis = 9.0;  // 3σ

// JᵀCJ for J = [I | −[q]×], the Jacobian of a point (or mean) q about the sensor.
Matrix6d pointInformation(const Matrix3d& c, const Vector3d& q) {
  const Matrix3d qx = skew(q);
  const Matrix3d cq = c * qx;
  Matrix6d h;
  h.topLeftCorner<3, 3>() = c;
  h.topRightCorner<3, 3>() = -cq;
  h.bottomLeftCorner<3, 3>() = -cq.transpose();
  h.bottomRightCorner<3, 3>() = -qx * cq;
  return h;
}

}  // namespace

void ObjectiveValue::add(const ObjectiveValue& other) {
  score += other.score;
  gradient += other.gradient;
  hessian += other.hessian;
  matched += other.matched;
  items += other.items;
}

void PoseInformation::add(const PoseInformation& other) {
  information += other.information;
  chi2 += other.chi2;
  terms += other.terms;
}

template <class Result, class PerItem>
Result NdtObjective::sumOverItems(PerItem&& per_item) const {
  const size_t n = scan_.size();
  const size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<Result> partial(chunks);
  const size_t threads = std::max<size_t>(1, std::min<size_t>(size_t(threads_), chunks));
  pool_.run(threads, [&](size_t t) {
    // Summed on this thread's stack, stored once: neighbouring chunks' sums share cache lines.
    for (size_t c = t; c < chunks; c += threads) {
      Result sum;
      for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) per_item(i, sum);
      partial[c] = sum;
    }
  });
  Result total;
  for (const Result& p : partial) total.add(p);
  return total;
}

ObjectiveValue NdtObjective::evaluate(const Eigen::Isometry3d& pose, bool derivatives) const {
  return sumOverItems<ObjectiveValue>([&](size_t i, ObjectiveValue& out) {
    if (method_ == RegistrationMethod::P2D)
      scorePoint(pose, i, derivatives, out);
    else
      scoreGaussian(pose, i, derivatives, out);
  });
}

PoseInformation NdtObjective::information(const Eigen::Isometry3d& pose) const {
  return sumOverItems<PoseInformation>(
      [&](size_t i, PoseInformation& out) { informationOfItem(pose, i, out); });
}

bool NdtObjective::matches(const Eigen::Isometry3d& pose, size_t i) const {
  ObjectiveValue one;
  if (method_ == RegistrationMethod::P2D)
    scorePoint(pose, i, false, one);
  else
    scoreGaussian(pose, i, false, one);
  return one.matched > 0;
}

// P2D (Magnusson 2009, eq. 6.12-6.13, in our parameters): f = d1·exp(−d2/2·s), s = eᵀCe,
// e = y − μ, y = q + t, q = R·x. With a = Ce and j = (a, q × a):
//   ∇f = −d2·f·j,   ∇²f = d2·f·[d2·j·jᵀ − JᵀCJ − diag(0, ½(a·qᵀ + q·aᵀ) − (a·q)·I)].
// A point's terms share J = [I | −[q]×], so the second and third parts are summed over the
// point's Gaussians first (Σ d2·f·C and Σ d2·f·a) and multiplied by J once per point.
void NdtObjective::scorePoint(const Eigen::Isometry3d& pose, size_t i, bool derivatives,
                              ObjectiveValue& out) const {
  const Vector3d q = pose.linear() * scan_.points[i];
  const Vector3d y = q + pose.translation();
  ++out.items;
  if (!map_.geometry().inRange(y)) return;
  const double s_max = 2 * kMaxExponent / k_.d2;
  bool matched = false;
  Matrix3d weighted_c = Matrix3d::Zero();  // Σ d2·f·C
  Vector3d weighted_a = Vector3d::Zero();   // Σ d2·f·a
  map_.forEachAround(map_.geometry().cellOf(y), [&](const PreparedGaussian& g) {
    const Vector3d e = y - g.mean;
    if (e.squaredNorm() > s_max * g.max_variance) return;  // s ≥ |e|²/λ_max > s_max
    const Vector3d a = g.information * e;
    const double s = e.dot(a);
    matched |= s < kMatchedSquaredMahalanobis;
    if (s > s_max) return;
    const double f = k_.d1 * std::exp(-0.5 * k_.d2 * s);
    out.score += f;
    if (!derivatives) return;
    Vector6d j;
    j << a, q.cross(a);
    const double w = k_.d2 * f;
    out.gradient -= w * j;
    out.hessian.noalias() += (w * k_.d2) * j * j.transpose();
    weighted_c += w * g.information;
    weighted_a += w * a;
  });
  out.matched += matched;
  if (!derivatives || weighted_a.isZero(0.0)) return;
  out.hessian -= pointInformation(weighted_c, q);
  out.hessian.bottomRightCorner<3, 3>() -=
      0.5 * (weighted_a * q.transpose() + q * weighted_a.transpose()) -
      weighted_a.dot(q) * Matrix3d::Identity();
}

// D2D (Stoyanov et al. 2012), scan Gaussian (μ, Σ) against map Gaussian (μⱼ, Σⱼ): m = q + t − μⱼ
// with q = Rμ, A = RΣRᵀ, B = (A + Σⱼ)⁻¹, u = Bm, s = mᵀu; the rotation turns A too. With
// a = Au and Dₖ = ∂m/∂δₖ − (∂Σ/∂δₖ)u (for rotations eₖ×q − eₖ×a + A(eₖ×u)):
//   sₖ  = 2uᵀ∂m/∂δₖ − uᵀ(∂Σ/∂δₖ)u      (translation: 2u; rotation: 2(q − a) × u)
//   sₖₗ = 2DₖᵀBDₗ + 2uᵀ∂²m/∂δₖ∂δₗ − uᵀ(∂²Σ/∂δₖ∂δₗ)u
// and f = d1·exp(−d2/2·s): ∇f = −d2/2·f·sₖ, ∇²f = d2/2·f·(d2/2·sₖsₗ − sₖₗ).
void NdtObjective::scoreGaussian(const Eigen::Isometry3d& pose, size_t i, bool derivatives,
                                 ObjectiveValue& out) const {
  const ScanGaussian& sg = scan_.gaussians[i];
  const Matrix3d& r = pose.linear();
  const Vector3d q = r * sg.mean;
  const Vector3d y = q + pose.translation();
  const Matrix3d cov = r * sg.covariance * r.transpose();
  ++out.items;
  if (!map_.geometry().inRange(y)) return;
  const double s_max = 2 * kMaxExponent / k_.d2;
  bool matched = false;
  map_.forEachAround(map_.geometry().cellOf(y), [&](const PreparedGaussian& g) {
    const Vector3d m = y - g.mean;
    // λ_max(A + Σⱼ) ≤ λ_max(A) + λ_max(Σⱼ), so s ≥ |m|² / (that sum).
    if (m.squaredNorm() > s_max * (sg.max_variance + g.max_variance)) return;
    const Matrix3d b = (cov + g.covariance).inverse();
    const Vector3d u = b * m;
    const double s = m.dot(u);
    matched |= s < kMatchedSquaredMahalanobis;
    if (s > s_max) return;
    const double f = k_.d1 * std::exp(-0.5 * k_.d2 * s);
    out.score += f;
    if (!derivatives) return;
    const Vector3d a = cov * u;
    Vector6d sk;
    sk << 2 * u, 2 * (q - a).cross(u);
    out.gradient -= (0.5 * k_.d2 * f) * sk;

    Eigen::Matrix<double, 3, 6> d;
    d.leftCols<3>().setIdentity();
    d.rightCols<3>() = skew(a - q) - cov * skew(u);  // columns eₖ×q − eₖ×a + A(eₖ×u)
    Matrix6d skl = 2 * d.transpose() * b * d;
    const Matrix3d ux = -skew(u), ax = -skew(a);  // columns eₖ × u, eₖ × a
    skl.bottomRightCorner<3, 3>() += u * q.transpose() + q * u.transpose() -
                                     2 * u.dot(q) * Matrix3d::Identity() + ux.transpose() * ax +
                                     ax.transpose() * ux - 2 * ux.transpose() * cov * ux;
    out.hessian += (0.5 * k_.d2 * f) * (0.5 * k_.d2 * sk * sk.transpose() - skl);
  });
  out.matched += matched;
}

void NdtObjective::informationOfItem(const Eigen::Isometry3d& pose, size_t i,
                                     PoseInformation& out) const {
  const bool p2d = method_ == RegistrationMethod::P2D;
  const Matrix3d& r = pose.linear();
  const Vector3d q = r * (p2d ? scan_.points[i] : scan_.gaussians[i].mean);
  const Vector3d y = q + pose.translation();
  if (!map_.geometry().inRange(y)) return;
  const Matrix3d cov =
      p2d ? Matrix3d::Zero() : Matrix3d(r * scan_.gaussians[i].covariance * r.transpose());
  map_.forEachAround(map_.geometry().cellOf(y), [&](const PreparedGaussian& g) {
    const Vector3d e = y - g.mean;
    if (e.squaredNorm() > kMatchedSquaredMahalanobis * (g.max_variance + cov.trace())) return;
    const Matrix3d c = p2d ? g.information : Matrix3d((cov + g.covariance).inverse());
    const double s = e.dot(c * e);
    if (s >= kMatchedSquaredMahalanobis) return;
    out.information += pointInformation(c, q);
    out.chi2 += s;
    ++out.terms;
  });
}

}  // namespace ndtom::registration
