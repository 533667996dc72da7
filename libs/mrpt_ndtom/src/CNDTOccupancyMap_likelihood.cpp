// CNDTOccupancyMap: observation likelihood (particle filters) and matching (ICP).
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "mrpt_ndtom/points_map.h"
#include "ndtom/localization/ndt_mcl.h"
#include "ndtom/matching/ndt_correspondences.h"
#include "ndtom/matching/ndt_likelihood.h"
#include "scan_ndt_cache.h"

namespace mrpt_ndtom {
using Eigen::Vector3d;

bool CNDTOccupancyMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const {
  return isSupportedObservation(obs);
}

double CNDTOccupancyMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const {
  // MRPT's particle filters abort unless this is finite. The unscaled sum is finite (every
  // term is at least the log of the outlier floor), and kMaxScale keeps it so once scaled; a
  // scale set in code past it would give -inf, so it is refused here, where it is used.
  const double scale = likelihoodOptions.scale;
  if (!(scale > 0 && scale <= TLikelihoodOptions::kMaxScale))
    THROW_EXCEPTION(
        mrpt::format("CNDTOccupancyMap::likelihoodOptions: scale = %g: must be in "
                     "(0, %g]",
                     scale, TLikelihoodOptions::kMaxScale));
  return likelihoodOptions.likelihood_method == TLikelihoodMethod::NdtMcl
             ? ndtMclLikelihood(obs, takenFrom)
             : pointsLikelihood(obs, takenFrom);
}

double CNDTOccupancyMap::pointsLikelihood(const mrpt::obs::CObservation& obs,
                                          const mrpt::poses::CPose3D& takenFrom) const {
  const TLikelihoodOptions& o = likelihoodOptions;
  const auto extracted = observationPoints(
      obs, takenFrom, TPointExtractionOptions{o.decimation, o.decimation_3d_range});
  if (!extracted) return 0.0;
  std::vector<Vector3d> points;
  points.reserve(extracted->points_world.size());
  for (const Vector3d& p : extracted->points_world) {
    const double range = (p - extracted->sensor_origin).norm();
    if (range >= o.min_range && range <= o.max_range) points.push_back(p);
  }
  ndtom::LikelihoodOptions core;
  core.outlier_likelihood = o.outlier_likelihood;
  core.search_neighbours = o.search_neighbours;
  return o.scale * ndtom::scanLikelihood(*gaussianLookup(), points, core).log_likelihood;
}

// The NDT is built in the robot frame (the sensor's pose on the robot applied), so a
// particle's pose is the transform to score it at. Every point is used: the NDT is built once
// per observation, not once per particle.
std::shared_ptr<const ndtom::ScanNdt> CNDTOccupancyMap::scanNdt(
    const mrpt::obs::CObservation& obs) const {
  const TLikelihoodOptions& o = likelihoodOptions;
  detail::ScanNdtKey key = detail::ScanNdtKey::of(obs);
  key.cell_size = m_map.options().resolution * o.ndt_mcl_scan_factor;
  key.max_gaussians = size_t(o.ndt_mcl_max_gaussians);
  key.min_range = o.min_range;
  key.max_range = o.max_range;
  key.min_eigen_ratio = m_map.options().regularization.min_eigen_ratio;
  key.min_eigen_abs = m_map.options().regularization.min_eigen_abs;
  if (!isSupportedObservation(obs)) return nullptr;
  return m_scan_ndts->get(key, [&] {
    // Options set in code were never checked: a negative count would keep every Gaussian.
    try {
      o.validate();
    } catch (const std::invalid_argument& e) {
      THROW_EXCEPTION(std::string("CNDTOccupancyMap::likelihoodOptions: ") + e.what());
    }
    const auto extracted = observationPoints(obs, mrpt::poses::CPose3D());
    std::vector<Vector3d> points;
    points.reserve(extracted->points_world.size());
    for (const Vector3d& p : extracted->points_world) {
      const double range = (p - extracted->sensor_origin).norm();
      if (range >= key.min_range && range <= key.max_range) points.push_back(p);
    }
    ndtom::ScanNdtOptions options;
    options.cell_size = key.cell_size;
    options.max_gaussians = key.max_gaussians;
    options.regularization = m_map.options().regularization;
    return ndtom::buildScanNdt(points, options);
  });
}

double CNDTOccupancyMap::ndtMclLikelihood(const mrpt::obs::CObservation& obs,
                                          const mrpt::poses::CPose3D& takenFrom) const {
  const TLikelihoodOptions& o = likelihoodOptions;
  const auto scan = scanNdt(obs);
  if (!scan) return 0.0;
  ndtom::NdtMclOptions core;
  core.outlier_likelihood = o.outlier_likelihood;
  return o.scale *
         ndtom::ndtMclLikelihood(*ndtMclMap(), *scan, toIsometry(takenFrom), core).log_likelihood;
}

void CNDTOccupancyMap::determineMatching3D(const mrpt::maps::CMetricMap* otherMap,
                                           const mrpt::poses::CPose3D& otherMapPose,
                                           mrpt::tfest::TMatchingPairList& correspondences,
                                           const mrpt::maps::TMatchingParams& params,
                                           mrpt::maps::TMatchingExtraResults& extraResults) const {
  determineMatching(otherMap, otherMapPose, correspondences, params, extraResults, false);
}

void CNDTOccupancyMap::determineMatching2D(const mrpt::maps::CMetricMap* otherMap,
                                           const mrpt::poses::CPose2D& otherMapPose,
                                           mrpt::tfest::TMatchingPairList& correspondences,
                                           const mrpt::maps::TMatchingParams& params,
                                           mrpt::maps::TMatchingExtraResults& extraResults) const {
  determineMatching(otherMap, mrpt::poses::CPose3D(otherMapPose), correspondences, params,
                    extraResults, true);
}

void CNDTOccupancyMap::determineMatching(const mrpt::maps::CMetricMap* otherMap,
                                         const mrpt::poses::CPose3D& otherMapPose,
                                         mrpt::tfest::TMatchingPairList& correspondences,
                                         const mrpt::maps::TMatchingParams& params,
                                         mrpt::maps::TMatchingExtraResults& extraResults,
                                         bool planar) const {
  correspondences.clear();
  extraResults = mrpt::maps::TMatchingExtraResults();
  const mrpt::maps::CPointsMap* other = asPointsMap(otherMap);
  if (!other) THROW_EXCEPTION("CNDTOccupancyMap::determineMatching: otherMap must be a CPointsMap");

  ndtom::CorrespondenceOptions co;
  co.max_distance = params.maxDistForCorrespondence;
  co.angular_tolerance = params.maxAngularDistForCorrespondence;
  co.pivot = Vector3d(params.angularDistPivotPoint.x, params.angularDistPivotPoint.y,
                      params.angularDistPivotPoint.z);
  co.first = params.offset_other_map_points;
  co.stride = std::max<size_t>(1, params.decimation_other_map_points);
  co.planar = planar;
  const auto result =
      ndtom::findCorrespondences(*gaussianLookup(), pointsOf(*other, otherMapPose), co);

  const auto &xs = other->getPointsBufferRef_x(), &ys = other->getPointsBufferRef_y(),
             &zs = other->getPointsBufferRef_z();
  correspondences.reserve(result.pairs.size());
  for (const auto& pair : result.pairs) {
    mrpt::tfest::TMatchingPair m;
    m.globalIdx = pair.gaussian;
    m.localIdx = pair.point;
    m.global = {float(pair.target.x()), float(pair.target.y()), float(pair.target.z())};
    m.local = {xs[pair.point], ys[pair.point], zs[pair.point]};
    m.errorSquareAfterTransformation = float(pair.squared_distance);
    extraResults.sumSqrDist += float(pair.squared_distance);
    correspondences.push_back(m);
  }
  if (result.points_considered > 0)
    extraResults.correspondencesRatio = float(result.pairs.size()) / result.points_considered;
}

namespace {

// The NDT map inside `map` (itself, or the first one of a CMultiMetricMap); null if none.
const CNDTOccupancyMap* asNdtMap(const mrpt::maps::CMetricMap* map) {
  if (const auto* ndt = dynamic_cast<const CNDTOccupancyMap*>(map)) return ndt;
  if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(map))
    for (const auto& m : multi->maps)
      if (const auto* ndt = dynamic_cast<const CNDTOccupancyMap*>(m.get())) return ndt;
  return nullptr;
}

// The means of the map's occupied cells with points, moved by `pose`: an NDT map's points.
std::vector<Vector3d> occupiedMeans(const ndtom::NdtMap& map, const mrpt::poses::CPose3D& pose) {
  const Eigen::Isometry3d t = toIsometry(pose);
  std::vector<Vector3d> means;
  map.forEachCellOrdered([&](const ndtom::CellView& c) {
    if (c.stats && c.stats->n > 0 && ndtom::cellState(map, c) == ndtom::CellState::Occupied)
      means.push_back(t * (map.geometry().cellCenter(c.index) + c.stats->relative_mean));
  });
  return means;
}

}  // namespace

float CNDTOccupancyMap::compute3DMatchingRatio(
    const mrpt::maps::CMetricMap* otherMap, const mrpt::poses::CPose3D& otherMapPose,
    const mrpt::maps::TMatchingRatioParams& params) const {
  std::vector<Vector3d> points;
  if (const CNDTOccupancyMap* ndt = asNdtMap(otherMap))
    points = occupiedMeans(ndt->ndtMap(), otherMapPose);
  else if (const mrpt::maps::CPointsMap* other = asPointsMap(otherMap))
    points = pointsOf(*other, otherMapPose);
  if (points.empty()) return 0.0f;
  return float(ndtom::matchingRatio(*gaussianLookup(), points, params.maxMahaDistForCorr));
}

}  // namespace mrpt_ndtom
