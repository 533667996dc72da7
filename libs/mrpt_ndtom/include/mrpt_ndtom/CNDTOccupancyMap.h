// CNDTOccupancyMap: an NDT Occupancy Map (Saarinen et al., ICRA 2013) as an MRPT metric map.
// A thin adapter: observations become world-frame points plus a sensor origin, and every
// algorithm runs in the ndtom core.
//
// In .ini files (CMultiMetricMap, TSetOfMetricMapInitializers) its short name is
// `ndtOccupancyMap`:
//
//   [MetricMap]
//   ndtOccupancyMap_count = 1
//   [MetricMap_ndtOccupancyMap_00_insertOpts]     ; TInsertionOptions
//   [MetricMap_ndtOccupancyMap_00_likelihoodOpts] ; TLikelihoodOptions
//   [MetricMap_ndtOccupancyMap_00_renderOpts]     ; TRenderOptions
//   [MetricMap_ndtOccupancyMap_00_creationOpts]   ; enableSaveAs3DObject, ... (all maps)
//
// The class is registered when its shared library is loaded (MRPT's plugin flags, LD_PRELOAD,
// or linking it).
//
// Threading: const methods may run concurrently (pf-localization shares one map across
// threads); the Gaussians prepared for likelihood and matching are built once per map state
// under a mutex and then shared read-only.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/system/COutputLogger.h>
#include <mrpt/typemeta/TEnumType.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>

#include "mrpt_ndtom/ndt_visualization.h"
#include "mrpt_ndtom/observation_points.h"
#include "ndtom/localization/ndt_mcl.h"
#include "ndtom/map/map_queries.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/matching/gaussian_lookup.h"

namespace mrpt_ndtom {
namespace detail {
class ScanNdtCache;
}

class CNDTOccupancyMap : public mrpt::maps::CMetricMap, public mrpt::system::COutputLogger {
  DEFINE_SERIALIZABLE(CNDTOccupancyMap, mrpt_ndtom)

 public:
  /// An empty map with default options and the given cell edge (m).
  explicit CNDTOccupancyMap(double resolution = 0.2);
  CNDTOccupancyMap(const CNDTOccupancyMap& other);
  CNDTOccupancyMap& operator=(const CNDTOccupancyMap& other);
  ~CNDTOccupancyMap() override = default;

  /// How observations are inserted (paper Sec. III): the core's MapOptions (resolution,
  /// occupancy.p_hit, scan.threads, ...; see ndtom/map/option_table.h for every option, its
  /// .ini key, unit and bounds) plus how points are taken from observations. Changes apply at
  /// the next insertion; the resolution can only change while the map is empty.
  class TInsertionOptions : public mrpt::config::CLoadableOptions, public ndtom::MapOptions {
   public:
    /// Throws (naming the section and option) if a loaded value is invalid.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    /// The options under a header naming them, as MRPT's own options print.
    void dumpToTextStream(std::ostream& out) const override;

    uint32_t decimation{1};           ///< Keep 1 point in N of scans and clouds (Default: 1)
    uint32_t decimation_3d_range{1};  ///< Depth images: every N-th row and column (Default: 1)

    /// The core's options; throws std::invalid_argument naming a bad value.
    ndtom::MapOptions toMapOptions() const;
    TPointExtractionOptions extractionOptions() const;
    void writeToStream(mrpt::serialization::CArchive& out) const;
    void readFromStream(mrpt::serialization::CArchive& in);
    bool operator==(const TInsertionOptions& o) const;
  };
  TInsertionOptions insertionOptions;

  /// How computeObservationLikelihood() scores an observation.
  enum class TLikelihoodMethod : int32_t {
    /// Each point against the best Gaussian near it (ndtom/matching/ndt_likelihood.h).
    Points = 0,
    /// NDT-MCL: the scan's own NDT, built once per observation, each of its Gaussians
    /// against the map Gaussian of its cell (ndtom/localization/ndt_mcl.h). Made for particle
    /// filters:
    /// a few hundred terms per particle.
    NdtMcl = 1
  };

  /// How computeObservationLikelihood() scores an observation.
  class TLikelihoodOptions : public mrpt::config::CLoadableOptions {
   public:
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    /// The options under a header naming them, as MRPT's own options print.
    void dumpToTextStream(std::ostream& out) const override;

    /// Points | NdtMcl (Default: Points)
    TLikelihoodMethod likelihood_method{TLikelihoodMethod::Points};
    uint32_t decimation{10};          ///< Points: score 1 point in N (Default: 10)
    uint32_t decimation_3d_range{8};  ///< Points, depth images: every N-th row, column (Default: 8)
    /// A point's (Points) or scan Gaussian's (NdtMcl) likelihood floor, in (0, 1)
    /// (Default: 0.05)
    double outlier_likelihood{0.05};
    /// Points: best Gaussian of the 27 cells around a point (Default: true)
    bool search_neighbours{true};
    double min_range{0.0};  ///< Closer points are not used (Default: 0 m)
    double max_range{std::numeric_limits<double>::infinity()};  ///< (Default: inf)
    /// Multiplies the summed log-likelihood: < 1 flattens particle weights, in
    /// (0, kMaxScale] (Default: 1)
    double scale{1.0};
    /// The largest scale: MRPT's particle filters assert that each observation's
    /// log-likelihood is finite, and sum those of a frame's observations and of a multi-map's
    /// maps first. A point's or scan Gaussian's log-likelihood is at least log of the smallest
    /// double, −745; with up to 10^12 of them in an observation, scale · 7.5·10^14 ≤ 10^300
    /// leaves 10^8 such terms below the largest double (1.8·10^308).
    static constexpr double kMaxScale = 1e280;
    /// NdtMcl: edge of the scan's cells, in map cells, in [1, 64] (Default: 2)
    int32_t ndt_mcl_scan_factor{2};
    /// NdtMcl: the map's exact coarsening the scan is scored against, in map cells, in
    /// [1, 64]; 1 is the map itself (Default: 1)
    int32_t ndt_mcl_map_factor{1};
    /// NdtMcl: scan Gaussians kept, those with the most points, in [1, 100000]; the cost per
    /// particle grows with it (Default: 300)
    int32_t ndt_mcl_max_gaussians{300};

    /// Throws std::invalid_argument naming a bad value.
    void validate() const;
    void writeToStream(mrpt::serialization::CArchive& out) const;
    void readFromStream(mrpt::serialization::CArchive& in);
    bool operator==(const TLikelihoodOptions& o) const;
  };
  TLikelihoodOptions likelihoodOptions;

  /// How getVisualizationInto() and getAsOctoMapVoxels() draw the map.
  TRenderOptions renderOptions;

  // --- The NDT-OM itself ---------------------------------------------------------------

  /// The core map (its options are those in force at the last insertion, except `threads`:
  /// insertPoints() passes insertionOptions.scan.threads with each scan).
  const ndtom::NdtMap& ndtMap() const { return m_map; }
  /// Replaces the contents, e.g. with a map loaded by ndtom::loadMap(); insertionOptions take
  /// the map's resolution, occupancy and regularisation options.
  void setNdtMap(ndtom::NdtMap map);
  /// Inserts world-frame points seen from `sensor_origin`, with insertionOptions' ranges, ray
  /// mode and threads. Returns the core's account of every point.
  ndtom::InsertionReport insertPoints(const std::vector<Eigen::Vector3d>& points_world,
                                      const Eigen::Vector3d& sensor_origin);
  /// What the last successful insertion did.
  const ndtom::InsertionReport& lastInsertionReport() const { return m_last_report; }

  /// A copy `factor` times coarser (paper Sec. III-B): each coarse cell is the exact merge
  /// of the fine cells inside it. Same likelihood and render options.
  Ptr getCoarsened(int factor) const;

  /// The prepared Gaussians of the current map state (built on first use, then shared).
  std::shared_ptr<const ndtom::GaussianLookup> gaussianLookup() const;
  /// The map's Gaussians as the NdtMcl likelihood scores against them: the exact coarsening by
  /// likelihoodOptions.ndt_mcl_map_factor (built on first use, then shared).
  std::shared_ptr<const ndtom::NdtMclMap> ndtMclMap() const;
  /// The NDT the NdtMcl likelihood builds of `obs` (robot frame), as likelihoodOptions say;
  /// nullptr for an unsupported observation. Kept while particles are scored with it.
  std::shared_ptr<const ndtom::ScanNdt> scanNdt(const mrpt::obs::CObservation& obs) const;

  // --- Queries (named as COctoMap's) -----------------------------------------------------

  /// Occupancy probability of the cell at (x, y, z); false where nothing is known.
  bool getPointOccupancy(float x, float y, float z, double& prob_occupancy) const;
  /// Occupied, free or unknown, by the one rule of ndtom::cellState().
  ndtom::CellState cellState(const mrpt::math::TPoint3D& point) const;
  /// Casts a ray from `origin` along `direction` (any non-zero length) and sets `end` to the
  /// centre of the first occupied cell it enters (the origin's own cell included), as
  /// COctoMap::castRay does. With ignoreUnknownCells false an unknown cell ends the search
  /// with no hit. maxRange <= 0: up to the far side of the map's bounding box. Returns
  /// whether a cell was hit; throws for a zero or non-finite ray. The exact entry point and
  /// distance: ndtom::castRay(ndtMap(), ...).
  bool castRay(const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& direction,
               mrpt::math::TPoint3D& end, bool ignoreUnknownCells = false,
               double maxRange = -1.0) const;
  /// The box of all known cells (free and occupied, cell faces included); all zeros for an
  /// empty map. (CMetricMap has no virtual boundingBox() in MRPT 2.5.)
  mrpt::math::TBoundingBox boundingBox() const;
  /// Fills `voxels` with the known cells, as COccupancyGridMap3D does: the occupied set
  /// (VOXEL_SET_OCCUPIED) and the free set (VOXEL_SET_FREESPACE), per renderOptions'
  /// generate_/visible_ flags, coloured by `voxels`' visualization mode and colour (by
  /// occupancy, height, ...). Unknown cells are left out.
  void getAsOctoMapVoxels(mrpt::opengl::COctoMapVoxels& voxels) const;

  // --- CMetricMap ------------------------------------------------------------------------

  bool isEmpty() const override;
  std::string asString() const override;
  /// Writes `<prefix>.ndtom` (the core's file format) and `<prefix>.3Dscene`.
  void saveMetricMapRepresentationToFile(const std::string& prefix) const override;
  /// Ellipsoids of the occupied Gaussians (see renderOptions), unless
  /// genericMapParams.enableSaveAs3DObject is false.
  void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;

  /// For ICP: pairs each point of `otherMap` (a CPointsMap) with its projection on the best
  /// nearby Gaussian (see ndtom/matching/ndt_correspondences.h). `global` is that projection in
  /// this map's frame, `local` the point in the other map's frame, `globalIdx` the Gaussian's index
  /// in gaussianLookup(). Honours maxDistForCorrespondence, maxAngularDistForCorrespondence,
  /// decimation_other_map_points and offset_other_map_points.
  void determineMatching3D(const mrpt::maps::CMetricMap* otherMap,
                           const mrpt::poses::CPose3D& otherMapPose,
                           mrpt::tfest::TMatchingPairList& correspondences,
                           const mrpt::maps::TMatchingParams& params,
                           mrpt::maps::TMatchingExtraResults& extraResults) const override;
  /// For MRPT's 2D ICP (CICP::Align with 2D poses): as determineMatching3D, but in the x-y
  /// plane: each point is paired with its foot on the x-y marginal of the best Gaussian (a
  /// wall's line), at the point's own height.
  void determineMatching2D(const mrpt::maps::CMetricMap* otherMap,
                           const mrpt::poses::CPose2D& otherMapPose,
                           mrpt::tfest::TMatchingPairList& correspondences,
                           const mrpt::maps::TMatchingParams& params,
                           mrpt::maps::TMatchingExtraResults& extraResults) const override;
  /// Fraction of the other map's points within Mahalanobis distance maxMahaDistForCorr of a
  /// Gaussian. The other map may be a points map, another CNDTOccupancyMap (its occupied
  /// cells' means are the points), or a CMultiMetricMap holding either (an NDT map first),
  /// as MRPT's map-partition hands it. 0 if it has no points.
  float compute3DMatchingRatio(const mrpt::maps::CMetricMap* otherMap,
                               const mrpt::poses::CPose3D& otherMapPose,
                               const mrpt::maps::TMatchingRatioParams& params) const override;
  /// Squared distance in the x-y plane from (x0, y0) to the nearest occupied Gaussian's
  /// mean; infinity for a map without Gaussians.
  float squareDistanceToClosestCorrespondence(float x0, float y0) const override;

 private:
  void internal_clear() override;
  bool internal_insertObservation(
      const mrpt::obs::CObservation& obs,
      const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
  double internal_computeObservationLikelihood(
      const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
  bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override;

  void determineMatching(const mrpt::maps::CMetricMap* otherMap,
                         const mrpt::poses::CPose3D& otherMapPose,
                         mrpt::tfest::TMatchingPairList& correspondences,
                         const mrpt::maps::TMatchingParams& params,
                         mrpt::maps::TMatchingExtraResults& extraResults, bool planar) const;
  double pointsLikelihood(const mrpt::obs::CObservation& obs,
                          const mrpt::poses::CPose3D& takenFrom) const;
  double ndtMclLikelihood(const mrpt::obs::CObservation& obs,
                          const mrpt::poses::CPose3D& takenFrom) const;

  /// Brings m_map's options in line with insertionOptions.
  void applyInsertionOptions();
  void invalidateLookup();
  void shareLookups(const CNDTOccupancyMap& other);

  ndtom::NdtMap m_map;
  ndtom::InsertionReport m_last_report;
  mutable std::mutex m_lookup_mutex;  ///< guards m_lookup, m_mcl_map and m_mcl_factor
  mutable std::shared_ptr<const ndtom::GaussianLookup> m_lookup;  ///< null when stale
  mutable std::shared_ptr<const ndtom::NdtMclMap> m_mcl_map;      ///< null when stale
  mutable int m_mcl_factor = 0;                                   ///< m_mcl_map's coarsening
  /// The Gaussians' means in the x-y plane, for squareDistanceToClosestCorrespondence.
  mutable std::shared_ptr<const ndtom::PointKdTree> m_means_xy;  ///< null when stale
  /// Each map object has its own (a copy starts with an empty one); never null.
  std::shared_ptr<detail::ScanNdtCache> m_scan_ndts;

  MAP_DEFINITION_START(CNDTOccupancyMap)
  mrpt_ndtom::CNDTOccupancyMap::TInsertionOptions insertionOpts;
  mrpt_ndtom::CNDTOccupancyMap::TLikelihoodOptions likelihoodOpts;
  mrpt_ndtom::TRenderOptions renderOpts;
  MAP_DEFINITION_END(CNDTOccupancyMap)
};

}  // namespace mrpt_ndtom

// Lets .ini files name the ray mode ("PerPoint", "PerHitCell") as well as number it.
MRPT_ENUM_TYPE_BEGIN(ndtom::RayMode)
MRPT_FILL_ENUM_MEMBER(ndtom::RayMode, PerPoint);
MRPT_FILL_ENUM_MEMBER(ndtom::RayMode, PerHitCell);
MRPT_ENUM_TYPE_END()

// The same for the likelihood method ("Points", "NdtMcl").
MRPT_ENUM_TYPE_BEGIN(mrpt_ndtom::CNDTOccupancyMap::TLikelihoodMethod)
MRPT_FILL_ENUM_MEMBER(mrpt_ndtom::CNDTOccupancyMap::TLikelihoodMethod, Points);
MRPT_FILL_ENUM_MEMBER(mrpt_ndtom::CNDTOccupancyMap::TLikelihoodMethod, NdtMcl);
MRPT_ENUM_TYPE_END()
