// CNDTOccupancyMap: registration, construction, options, serialization.
#include "mrpt_ndtom/CNDTOccupancyMap.h"

#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

#include "archive_checks.h"
#include "mrpt_ndtom/encoded_archive.h"
#include "ndtom/files/map_io.h"
#include "ndtom/map/option_table.h"
#include "scan_ndt_cache.h"

using mrpt_ndtom::CNDTOccupancyMap;

//  =========== Begin of Map definition ============
MAP_DEFINITION_REGISTER("mrpt_ndtom::CNDTOccupancyMap,ndtOccupancyMap",
                        mrpt_ndtom::CNDTOccupancyMap)

CNDTOccupancyMap::TMapDefinition::TMapDefinition() = default;

void CNDTOccupancyMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix) {
  // [<sectionNamePrefix>_creationOpts] holds only genericMapParams, read by the base class.
  insertionOpts.loadFromConfigFile(source, sectionNamePrefix + "_insertOpts");
  likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
  renderOpts.loadFromConfigFile(source, sectionNamePrefix + "_renderOpts");
}

void CNDTOccupancyMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const {
  insertionOpts.dumpToTextStream(out);
  likelihoodOpts.dumpToTextStream(out);
  renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CNDTOccupancyMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& definition) {
  const auto& def = dynamic_cast<const CNDTOccupancyMap::TMapDefinition&>(definition);
  auto* map = new CNDTOccupancyMap(def.insertionOpts.resolution);
  map->insertionOptions = def.insertionOpts;
  map->likelihoodOptions = def.likelihoodOpts;
  map->renderOptions = def.renderOpts;
  map->applyInsertionOptions();
  return map;
}
//  =========== End of Map definition Block =========

IMPLEMENTS_SERIALIZABLE(CNDTOccupancyMap, CMetricMap, mrpt_ndtom)

// Without this, deserialising the class (and so copying a CMultiMetricMap, as rbpf-slam
// does) fails with "class not registered". A static object rather than MRPT_INITIALIZER: the
// runtimeClassId defined just above is initialised at run time (it holds a std::function),
// and only a variable defined after it in this file is sure to be initialised after it. An
// __attribute__((constructor)) function may run first (clang does): it registered an empty id.
namespace {
struct RegisterClasses {
  RegisterClasses() { mrpt::rtti::registerClass(CLASS_ID(mrpt_ndtom::CNDTOccupancyMap)); }
} const register_classes;
}  // namespace

namespace mrpt_ndtom {
namespace {

// The first option in which a and b differ, as "name (a vs b)"; empty if none. Machine options
// (threads, memory budget) are left out: they do not change the map, so a new value must not
// rebuild it (insertPoints passes them with each scan).
std::string optionDifference(const ndtom::MapOptions& a, const ndtom::MapOptions& b) {
  const ndtom::OptionRow* row = ndtom::firstDifference(a, b, ndtom::OptionScope::Map);
  return row ? mrpt::format("%s (%.17g vs %.17g)", row->name, row->get(a), row->get(b))
             : std::string();
}

bool sameOptions(const ndtom::MapOptions& a, const ndtom::MapOptions& b) {
  return !ndtom::firstDifference(a, b, ndtom::OptionScope::Map);
}

ndtom::MapOptions mapOptionsOf(const CNDTOccupancyMap::TInsertionOptions& options) {
  try {
    return options.toMapOptions();
  } catch (const std::exception& e) {
    THROW_EXCEPTION(std::string("CNDTOccupancyMap::insertionOptions: ") + e.what());
  }
}

// `map` under options `wanted`: a fresh map if it is empty, else the same cells merged into a
// map with the new occupancy bounds or regularisation. The resolution of cells cannot change.
ndtom::NdtMap mapUnder(const ndtom::NdtMap& map, const ndtom::MapOptions& wanted) {
  if (map.isEmpty()) return ndtom::NdtMap(wanted);
  if (wanted.resolution != map.options().resolution)
    THROW_EXCEPTION(mrpt::format(
        "CNDTOccupancyMap: resolution cannot change from %g m to %g m once the map holds "
        "data; clear() the map first",
        map.options().resolution, wanted.resolution));
  ndtom::NdtMap rebuilt(wanted);
  rebuilt.merge(map);
  return rebuilt;
}

// The `size` bytes of the map data, read in chunks so that a corrupt size fails at the end of
// the data present, not in one huge allocation; a size over the memory budget (a compressed
// archive can expand a thousandfold) is refused before reading.
std::vector<uint8_t> readMapBytes(mrpt::serialization::CArchive& in, uint64_t size,
                                  uint64_t budget) {
  if (size > budget)
    throw ndtom::MemoryBudgetError(
        "CNDTOccupancyMap: map data of " + std::to_string(size) + " bytes in the archive", size,
        budget);
  constexpr uint64_t kChunk = uint64_t(1) << 20;
  std::vector<uint8_t> bytes;
  try {
    while (bytes.size() < size) {
      size_t offset = bytes.size();
      bytes.resize(offset + size_t(std::min(kChunk, size - offset)));
      // ReadBuffer may return less than asked (e.g. at the end); it throws when nothing is left.
      while (offset < bytes.size())
        offset += in.ReadBuffer(bytes.data() + offset, bytes.size() - offset);
    }
  } catch (const std::exception&) {
    THROW_EXCEPTION(mrpt::format(
        "CNDTOccupancyMap: the archive ends inside the map data (%llu bytes announced)",
        static_cast<unsigned long long>(size)));
  }
  return bytes;
}

ndtom::MapOptions withResolution(double resolution) {
  ndtom::MapOptions o;
  o.resolution = resolution;
  return o;
}

}  // namespace

CNDTOccupancyMap::CNDTOccupancyMap(double resolution)
    : mrpt::system::COutputLogger("CNDTOccupancyMap"),
      m_map(withResolution(resolution)),
      m_scan_ndts(std::make_shared<detail::ScanNdtCache>()) {
  insertionOptions.resolution = resolution;
}

CNDTOccupancyMap::CNDTOccupancyMap(const CNDTOccupancyMap& other)
    : mrpt::maps::CMetricMap(other),
      mrpt::system::COutputLogger(other),
      insertionOptions(other.insertionOptions),
      likelihoodOptions(other.likelihoodOptions),
      renderOptions(other.renderOptions),
      m_map(other.m_map),
      m_last_report(other.m_last_report),
      m_scan_ndts(std::make_shared<detail::ScanNdtCache>()) {
  shareLookups(other);
}

CNDTOccupancyMap& CNDTOccupancyMap::operator=(const CNDTOccupancyMap& other) {
  if (this == &other) return *this;
  mrpt::maps::CMetricMap::operator=(other);
  mrpt::system::COutputLogger::operator=(other);
  insertionOptions = other.insertionOptions;
  likelihoodOptions = other.likelihoodOptions;
  renderOptions = other.renderOptions;
  m_map = other.m_map;
  m_last_report = other.m_last_report;
  shareLookups(other);
  return *this;
}

// The prepared Gaussians are immutable: a copy of the same map state may share them.
void CNDTOccupancyMap::shareLookups(const CNDTOccupancyMap& other) {
  std::shared_ptr<const ndtom::GaussianLookup> lookup;
  std::shared_ptr<const ndtom::NdtMclMap> mcl_map;
  std::shared_ptr<const ndtom::PointKdTree> means_xy;
  int mcl_factor;
  {
    std::lock_guard<std::mutex> lock(other.m_lookup_mutex);
    lookup = other.m_lookup;
    mcl_map = other.m_mcl_map;
    means_xy = other.m_means_xy;
    mcl_factor = other.m_mcl_factor;
  }
  std::lock_guard<std::mutex> lock(m_lookup_mutex);
  m_lookup = std::move(lookup);
  m_mcl_map = std::move(mcl_map);
  m_means_xy = std::move(means_xy);
  m_mcl_factor = mcl_factor;
}

std::shared_ptr<const ndtom::GaussianLookup> CNDTOccupancyMap::gaussianLookup() const {
  std::lock_guard<std::mutex> lock(m_lookup_mutex);
  if (!m_lookup) m_lookup = std::make_shared<const ndtom::GaussianLookup>(m_map);
  return m_lookup;
}

std::shared_ptr<const ndtom::NdtMclMap> CNDTOccupancyMap::ndtMclMap() const {
  const int factor = likelihoodOptions.ndt_mcl_map_factor;
  ASSERTMSG_(factor >= 1, "likelihoodOptions.ndt_mcl_map_factor must be >= 1");
  std::lock_guard<std::mutex> lock(m_lookup_mutex);
  if (!m_mcl_map || m_mcl_factor != factor) {
    m_mcl_map = factor == 1 ? std::make_shared<const ndtom::NdtMclMap>(m_map)
                            : std::make_shared<const ndtom::NdtMclMap>(m_map.coarsened(factor));
    m_mcl_factor = factor;
  }
  return m_mcl_map;
}

void CNDTOccupancyMap::invalidateLookup() {
  std::lock_guard<std::mutex> lock(m_lookup_mutex);
  m_lookup.reset();
  m_mcl_map.reset();
  m_means_xy.reset();
}

void CNDTOccupancyMap::applyInsertionOptions() {
  const ndtom::MapOptions wanted = mapOptionsOf(insertionOptions);
  if (sameOptions(wanted, m_map.options())) return;
  m_map = mapUnder(m_map, wanted);
  invalidateLookup();
}

void CNDTOccupancyMap::setNdtMap(ndtom::NdtMap map) {
  // The map's own options; the machine's (threads, memory budget) stay this object's.
  ndtom::copyOptions(map.options(), insertionOptions, ndtom::OptionScope::Map);
  m_map = std::move(map);
  m_last_report = {};
  invalidateLookup();
}

CNDTOccupancyMap::Ptr CNDTOccupancyMap::getCoarsened(int factor) const {
  ASSERTMSG_(factor >= 1, "getCoarsened: factor must be >= 1");
  auto coarse = std::make_shared<CNDTOccupancyMap>(m_map.options().resolution * factor);
  coarse->genericMapParams = genericMapParams;
  coarse->likelihoodOptions = likelihoodOptions;
  coarse->renderOptions = renderOptions;
  coarse->setNdtMap(m_map.coarsened(factor));
  coarse->insertionOptions.decimation = insertionOptions.decimation;
  coarse->insertionOptions.decimation_3d_range = insertionOptions.decimation_3d_range;
  coarse->insertionOptions.scan.threads = insertionOptions.scan.threads;
  return coarse;
}

bool CNDTOccupancyMap::isEmpty() const {
  return m_map.isEmpty();
}

std::string CNDTOccupancyMap::asString() const {
  return mrpt::format(
      "NDT-OM map (CNDTOccupancyMap): resolution %g m, %zu cells, %zu Gaussians, %zu occupied, "
      "%.1f MB",
      m_map.options().resolution, m_map.numCells(), m_map.numGaussians(), m_map.numOccupied(),
      m_map.memoryBytes() / 1e6);
}

void CNDTOccupancyMap::internal_clear() {
  m_map.clear();  // options follow insertionOptions again at the next insertion
  m_last_report = {};
  invalidateLookup();
}

// Insertion, likelihood and render options, genericMapParams, then the map in the core's file
// format (versioned and checksummed on its own). Version 0 held format version 1 (a record per
// cell); version 1 holds the compact format 2 (presence masks, log-odds runs). The core reads
// both, so both versions load the same way. Each options block has its own version byte: a
// new option bumps that (insertion options 1 added threads), not this.
namespace {
/// The encoding writeWithEncodedMap hands to serializeTo, for that map only.
struct EncodedMap {
  const CNDTOccupancyMap* map = nullptr;
  const std::vector<uint8_t>* bytes = nullptr;
};
thread_local EncodedMap t_encoded_map;
}  // namespace

uint8_t CNDTOccupancyMap::serializeGetVersion() const {
  return 1;
}

void CNDTOccupancyMap::serializeTo(mrpt::serialization::CArchive& out) const {
  insertionOptions.writeToStream(out);
  likelihoodOptions.writeToStream(out);
  renderOptions.writeToStream(out);
  out << genericMapParams;
  // Options changed since the last insertion apply to the written map (as they would at the
  // next insertion): the stored options and map always agree, which loading checks.
  std::optional<ndtom::NdtMap> pending;
  const ndtom::MapOptions wanted = mapOptionsOf(insertionOptions);
  if (!sameOptions(wanted, m_map.options())) pending = mapUnder(m_map, wanted);
  const ndtom::NdtMap& map = pending ? *pending : m_map;
  // Encoded once, then sized and written: file format 2 takes a fraction of the map's memory
  // (5.9 B per known cell against ~17 on the lidar map), and sizing it by a second encoding
  // cost as much as the first. writeWithEncodedMap hands the encoding over instead.
  std::vector<uint8_t> own;
  const bool given = !pending && t_encoded_map.map == this;
  if (!given) own = ndtom::encodeMap(map);
  const std::vector<uint8_t>& bytes = given ? *t_encoded_map.bytes : own;
  out << uint64_t(bytes.size());
  out.WriteBuffer(bytes.data(), bytes.size());
}

void writeWithEncodedMap(mrpt::serialization::CArchive& out, const CNDTOccupancyMap& map,
                         const std::vector<uint8_t>& encoded) {
  // Per thread: another thread serialising any map meanwhile encodes as usual.
  struct Given {
    explicit Given(const EncodedMap& e) { t_encoded_map = e; }
    ~Given() { t_encoded_map = {}; }
  } given(EncodedMap{&map, &encoded});
  out << map;
}

// Corrupt data throws a std::exception naming the problem and leaves the map as it was:
// everything is read and checked first.
void CNDTOccupancyMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  switch (version) {
    case 0:
    case 1: {
      TInsertionOptions insertion;
      TLikelihoodOptions likelihood;
      TRenderOptions render;
      mrpt::maps::TMapGenericParams generic;
      insertion.readFromStream(in);
      likelihood.readFromStream(in);
      render.readFromStream(in);
      in >> generic;
      detail::checkBoolBytes(generic.enableSaveAs3DObject, "genericMapParams.enableSaveAs3DObject");
      detail::checkBoolBytes(generic.enableObservationLikelihood,
                             "genericMapParams.enableObservationLikelihood");
      detail::checkBoolBytes(generic.enableObservationInsertion,
                             "genericMapParams.enableObservationInsertion");
      uint64_t size = 0;
      in >> size;
      // This object's budget (insertion.scan.memory_budget is this object's too): a corrupt
      // archive cannot raise it.
      const uint64_t budget = insertion.toMapOptions().scan.memory_budget;
      const std::vector<uint8_t> bytes = readMapBytes(in, size, budget);
      ndtom::NdtMap map =
          ndtom::decodeMap(bytes.data(), bytes.size(), "MRPT archive (CNDTOccupancyMap)", budget);
      // An archive whose options disagree with its map would silently rebuild (or fail) at
      // the next insertion: this program never writes one.
      const std::string difference = optionDifference(insertion.toMapOptions(), map.options());
      if (!difference.empty())
        THROW_EXCEPTION(
            "CNDTOccupancyMap: the archive's insertion options and its map data disagree: " +
            difference + ", options vs map");
      insertionOptions = insertion;
      likelihoodOptions = likelihood;
      renderOptions = render;
      genericMapParams = generic;
      m_map = std::move(map);
      m_last_report = {};
      invalidateLookup();
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

}  // namespace mrpt_ndtom
