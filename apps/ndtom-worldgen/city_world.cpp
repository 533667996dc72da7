#include "city_world.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace ndtom::world {
namespace {

// Uniform in [lo, hi) from the generator, identical on every platform (std::uniform_real_
// distribution is not specified bit for bit).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53;
}

}  // namespace

std::optional<double> rayBoxEntry(const Eigen::Vector3d& o, const Eigen::Vector3d& inverse_dir,
                                  const Box& box, double t_max) {
  double t0 = 0, t1 = t_max;
  for (int k = 0; k < 3; ++k) {
    double a = (box.lo[k] - o[k]) * inverse_dir[k], b = (box.hi[k] - o[k]) * inverse_dir[k];
    if (std::isnan(a) || std::isnan(b)) {  // parallel to the slab, on its boundary
      if (o[k] < box.lo[k] || o[k] > box.hi[k]) return std::nullopt;
      continue;
    }
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return std::nullopt;
  }
  return t0;
}

CityWorld::CityWorld(const CityLayout& l) : layout_(l) {
  if (l.blocks_x < 1 || l.blocks_y < 1 || !(l.street_width > 0) ||
      !(l.block_pitch > l.street_width + 10))
    throw std::invalid_argument(
        "city: blocks ≥ 1 per side and a pitch over the street width + 10 m");
  grid_origin_ = Eigen::Vector2d(-l.block_pitch, -l.block_pitch);
  cells_x_ = int(std::ceil((l.blocks_x + 2) * l.block_pitch / kCell));
  cells_y_ = int(std::ceil((l.blocks_y + 2) * l.block_pitch / kCell));

  std::mt19937_64 rng(l.seed);
  const double half_street = l.street_width / 2, inner = l.block_pitch - l.street_width;
  for (int bx = 0; bx < l.blocks_x; ++bx)
    for (int by = 0; by < l.blocks_y; ++by) {
      if (l.identical_blocks) rng.seed(l.seed);
      const double x0 = bx * l.block_pitch + half_street, y0 = by * l.block_pitch + half_street;
      const int lots_x = 2 + int(rng() % 2), lots_y = 2 + int(rng() % 2);
      const double lot_w = inner / lots_x, lot_d = inner / lots_y;
      for (int i = 0; i < lots_x; ++i)
        for (int j = 0; j < lots_y; ++j) {
          const double lx = x0 + i * lot_w, ly = y0 + j * lot_d;
          if (rng() % 8 == 0) {  // a park: a few trees
            for (int t = 0, n = 2 + int(rng() % 4); t < n; ++t) {
              const double cx = uniform(rng, lx + 2, lx + lot_w - 2),
                           cy = uniform(rng, ly + 2, ly + lot_d - 2);
              addBox({{cx - 0.2, cy - 0.2, 0}, {cx + 0.2, cy + 0.2, 3}});  // trunk
              const double r = uniform(rng, 1.5, 2.5), top = uniform(rng, 5, 9);
              addBox({{cx - r, cy - r, 3}, {cx + r, cy + r, top}});  // crown
            }
            continue;
          }
          const double setback = uniform(rng, 1, 4), height = uniform(rng, 6, 40);
          addBox({{lx + setback, ly + setback, 0},
                  {lx + lot_w - uniform(rng, 0.5, 3), ly + lot_d - uniform(rng, 0.5, 3), height}});
        }
      // Along the block's four curbs: poles every ~25 m, and parked cars.
      for (int side = 0; side < 4; ++side) {
        const bool along_x = side < 2;
        const double length = inner;
        for (double s = uniform(rng, 3, 10); s < length - 3; s += uniform(rng, 20, 30)) {
          const double off = 0.8;  // from the curb, on the sidewalk side
          const double px = along_x ? x0 + s : (side == 2 ? x0 + off : x0 + inner - off);
          const double py = along_x ? (side == 0 ? y0 + off : y0 + inner - off) : y0 + s;
          addBox({{px - 0.15, py - 0.15, 0}, {px + 0.15, py + 0.15, 6}});
        }
        for (double s = uniform(rng, 2, 8); s < length - 6; s += uniform(rng, 6, 20)) {
          if (rng() % 3 == 0) continue;
          const double curb = 1.2;  // the car's centre, street side of the curb
          const double cx = along_x ? x0 + s + 2.25 : (side == 2 ? x0 - curb : x0 + inner + curb);
          const double cy = along_x ? (side == 0 ? y0 - curb : y0 + inner + curb) : y0 + s + 2.25;
          const Eigen::Vector3d half =
              along_x ? Eigen::Vector3d(2.25, 0.9, 0.75) : Eigen::Vector3d(0.9, 2.25, 0.75);
          addBox({{cx - half.x(), cy - half.y(), 0}, {cx + half.x(), cy + half.y(), 1.5}});
        }
      }
    }
  buildGrid();
}

void CityWorld::addBox(const Box& box) {
  boxes_.push_back(box);
}

CityWorld::CellRange CityWorld::cellsUnder(const Box& box) const {
  return {std::max(0, int(std::floor((box.lo.x() - grid_origin_.x()) / kCell))),
          std::max(0, int(std::floor((box.lo.y() - grid_origin_.y()) / kCell))),
          std::min(cells_x_ - 1, int(std::floor((box.hi.x() - grid_origin_.x()) / kCell))),
          std::min(cells_y_ - 1, int(std::floor((box.hi.y() - grid_origin_.y()) / kCell)))};
}

// Two passes over the boxes: how many each cell holds, then which (in the order added).
void CityWorld::buildGrid() {
  const size_t cells = size_t(cells_x_) * size_t(cells_y_);
  cell_start_.assign(cells + 1, 0);
  uint64_t entries = 0;
  for (const Box& box : boxes_) {
    const CellRange r = cellsUnder(box);
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x)
        ++cell_start_[size_t(y) * size_t(cells_x_) + size_t(x) + 1];
    entries += uint64_t(std::max(0, r.x1 - r.x0 + 1)) * uint64_t(std::max(0, r.y1 - r.y0 + 1));
  }
  if (entries > UINT32_MAX || boxes_.size() > UINT32_MAX)
    throw std::invalid_argument("city: over 4 billion boxes in its grid cells");
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_boxes_.resize(size_t(entries));
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t b = 0; b < boxes_.size(); ++b) {
    const CellRange r = cellsUnder(boxes_[b]);
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x)
        cell_boxes_[fill[size_t(y) * size_t(cells_x_) + size_t(x)]++] = uint32_t(b);
  }
}

CityWorld::BoxList CityWorld::cellBoxes(int cx, int cy) const {
  const size_t c = size_t(cy) * size_t(cells_x_) + size_t(cx);
  return {cell_boxes_.data() + cell_start_[c], cell_boxes_.data() + cell_start_[c + 1]};
}

uint64_t CityWorld::memoryBytes() const {
  return boxes_.capacity() * sizeof(Box) +
         (cell_start_.capacity() + cell_boxes_.capacity()) * sizeof(uint32_t);
}

uint64_t CityWorld::estimatedBytes(const CityLayout& l) {
  // Measured: 25-30 boxes and 120-150 grid entries a block on average (seeds 1-20, 4-64
  // blocks a side); bounded here by 40 and 200. The boxes' vector may double while it
  // grows (twice the boxes), and building the grid holds a second copy of its starts.
  constexpr double kBoxesPerBlock = 40, kEntriesPerBlock = 200;
  const double blocks = double(std::max(l.blocks_x, 0)) * double(std::max(l.blocks_y, 0));
  const double cells = std::ceil((l.blocks_x + 2) * l.block_pitch / kCell) *
                       std::ceil((l.blocks_y + 2) * l.block_pitch / kCell);
  const double bytes =
      blocks * (2 * kBoxesPerBlock * sizeof(Box) + kEntriesPerBlock * 4) + 2 * cells * 4;
  return bytes >= 1.8e19 ? UINT64_MAX : uint64_t(bytes);
}

std::optional<double> CityWorld::castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                         double max_range) const {
  double best = max_range;
  bool hit = false;
  if (d.z() < 0 && o.z() >= 0) {
    const double t = -o.z() / d.z();
    if (t <= best) best = t, hit = true;
  }
  const Eigen::Vector3d inverse = d.cwiseInverse();
  // 2D walk through the cells under the ray (Amanatides-Woo), nearest first: stop once the
  // best hit lies before the next cell.
  const Eigen::Vector2d p = (o.head<2>() - grid_origin_) / kCell;
  int cx = int(std::floor(p.x())), cy = int(std::floor(p.y()));
  const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
  const double dx = std::abs(d.x()) / kCell, dy = std::abs(d.y()) / kCell;  // cells per metre
  double next_x = dx > 0 ? ((step_x > 0 ? cx + 1 - p.x() : p.x() - cx) / dx) : INFINITY;
  double next_y = dy > 0 ? ((step_y > 0 ? cy + 1 - p.y() : p.y() - cy) / dy) : INFINITY;
  const double delta_x = dx > 0 ? 1 / dx : INFINITY, delta_y = dy > 0 ? 1 / dy : INFINITY;
  double t_cell = 0;
  while (t_cell <= best) {
    if (cx >= 0 && cy >= 0 && cx < cells_x_ && cy < cells_y_)
      for (const uint32_t b : cellBoxes(cx, cy))
        if (const auto t = rayBoxEntry(o, inverse, boxes_[b], best)) {
          best = *t;
          hit = true;
        }
    // Leaving the grid for good ends the walk.
    if ((cx < 0 && step_x < 0) || (cy < 0 && step_y < 0) || (cx >= cells_x_ && step_x > 0) ||
        (cy >= cells_y_ && step_y > 0))
      break;
    if (next_x < next_y) {
      t_cell = next_x;
      next_x += delta_x;
      cx += step_x;
    } else {
      t_cell = next_y;
      next_y += delta_y;
      cy += step_y;
    }
  }
  return hit ? std::optional<double>(best) : std::nullopt;
}

bool CityWorld::isInside(const Eigen::Vector3d& p) const {
  if (p.z() < 0) return true;
  const int cx = int(std::floor((p.x() - grid_origin_.x()) / kCell));
  const int cy = int(std::floor((p.y() - grid_origin_.y()) / kCell));
  if (cx < 0 || cy < 0 || cx >= cells_x_ || cy >= cells_y_) return false;
  for (const uint32_t b : cellBoxes(cx, cy))
    if ((p.array() >= boxes_[b].lo.array()).all() && (p.array() <= boxes_[b].hi.array()).all())
      return true;
  return false;
}

}  // namespace ndtom::world
