// The message one process of a distributed build sends another per scan when the rays are
// shared out (count_exchange.h). A head: the sender's share of the scan's point counts (six
// words: hits, truncated, then the rejected by reason), the number h of hits it classified
// in the receiver's tiles and those hits (three doubles each, as six words). Then the
// free-space counts: per block, its coordinates, the number n of its cells counted, then n
// pairs (offset in the block, count). Private to the library.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/insertion_report.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

/// Starts a message with the point counts of `counts` (a scan has under 2^32 points) and the
/// hits [hits, hits + n).
void appendMessageHead(const InsertionReport& counts, const Eigen::Vector3d* hits, size_t n,
                       std::vector<uint32_t>& words);

/// Reads a message's head: adds its point counts to `counts` and appends its hits to `hits`.
/// Returns where its count blocks start. Throws std::runtime_error for a malformed head, or a
/// hit not finite or not in `owned`'s tiles.
size_t readMessageHead(const std::vector<uint32_t>& words, const TileOwnership& owned,
                       const GridGeometry& geometry, InsertionReport& counts,
                       std::vector<Eigen::Vector3d>& hits);

/// Appends a block's non-zero counts (`counts`: kBlockCells of them, in offset order). A block
/// with no count goes too: the walk that entered it made it part of the scan.
void appendCountBlock(const CellIndex& block, const uint32_t* counts, std::vector<uint32_t>& words);

/// Adds the count blocks of a message, from word `at` on, to `countsOf(block)` (kBlockCells
/// counters of that block). Throws std::runtime_error for a malformed message, or one naming
/// a block `owned` does not own; counts added before the error stay added.
void addCountMessage(const std::vector<uint32_t>& words, size_t at, const TileOwnership& owned,
                     const std::function<uint32_t*(const CellIndex& block)>& countsOf);

/// The error a malformed message is refused with.
std::runtime_error malformedMessage();

}  // namespace ndtom
