// Drawing: every ellipsoid vertex lies on the k-σ surface of its Gaussian (checked with the
// core's covariance and a direct inverse), culling keeps the best-supported Gaussians,
// enableSaveAs3DObject is honoured, and saveMetricMapRepresentationToFile writes a map file
// and a scene that load back.
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfTriangles.h>
#include <mrpt/system/filesystem.h>

#include <Eigen/LU>
#include <array>
#include <random>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"

using Eigen::Vector3d;
using mrpt_ndtom::CNDTOccupancyMap;

namespace {

// A few blobs of different sizes and a floor, seen from above.
CNDTOccupancyMap::Ptr sampleMap() {
  auto map = CNDTOccupancyMap::Create(0.5);
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0, 1);
  std::vector<Vector3d> points;
  for (int i = 0; i < 4000; ++i)
    points.emplace_back(0.1 + 0.8 * (i % 40) / 40.0, 0.1 + 0.8 * (i / 40 % 40) / 40.0, 0.2);
  for (int i = 0; i < 500; ++i)
    points.emplace_back(3.25 + 0.05 * n(rng), 0.25, 1.25 + 0.02 * n(rng));
  for (int i = 0; i < 30; ++i) points.emplace_back(-2.25 + 0.05 * n(rng), 1.25, 0.75);
  map->insertPoints(points, Vector3d(0.5, 0.5, 5.0));
  return map;
}

std::array<uint8_t, 3> pixel(const mrpt::img::CImage& image, unsigned x, unsigned y) {
  return {image.at<uint8_t>(x, y, 0), image.at<uint8_t>(x, y, 1), image.at<uint8_t>(x, y, 2)};
}

std::shared_ptr<mrpt::opengl::CSetOfTriangles> meshOf(mrpt::opengl::CSetOfObjects& objs) {
  return std::dynamic_pointer_cast<mrpt::opengl::CSetOfTriangles>(
      objs.getByName("ndtom_gaussians"));
}

}  // namespace

TEST(Visualization, EllipsoidVerticesLieOnTheSigmaSurface) {
  const auto map = sampleMap();
  const auto& ndt = map->ndtMap();
  for (const double k : {1.0, 2.0}) {
    mrpt_ndtom::TRenderOptions options;
    options.quantiles = k;
    options.subdivisions = 1;
    mrpt::opengl::CSetOfObjects objs;
    mrpt_ndtom::buildNdtVisualization(ndt, options, objs);
    const auto mesh = meshOf(objs);
    ASSERT_TRUE(mesh);
    const size_t per = mrpt_ndtom::trianglesPerEllipsoid(1);
    EXPECT_EQ(per, 32u);
    ASSERT_EQ(mesh->getTrianglesCount(), ndt.numGaussians() * per);

    // Gaussians are drawn in cell order, as forEachCellOrdered lists them.
    std::vector<ndtom::Gaussian> gaussians;
    ndt.forEachCellOrdered([&](const ndtom::CellView& c) {
      if (c.stats && c.stats->hasGaussian())
        gaussians.push_back(ndt.gaussianOf(c, ndtom::Covariance::Regularized));
    });
    for (size_t g = 0; g < gaussians.size(); ++g) {
      const Eigen::Matrix3d inv = gaussians[g].covariance.inverse();
      for (size_t t = 0; t < per; ++t) {
        mrpt::opengl::TTriangle tri;
        mesh->getTriangle(g * per + t, tri);
        for (int v = 0; v < 3; ++v) {
          const auto& pt = tri.vertices[v].xyzrgba.pt;
          const Vector3d d = Vector3d(pt.x, pt.y, pt.z) - gaussians[g].mean;
          EXPECT_NEAR(std::sqrt(d.dot(inv * d)), k, 1e-3 * k) << "gaussian " << g;
          // Normals point outwards.
          const auto& nv = tri.vertices[v].normal;
          EXPECT_GT(Vector3d(nv.x, nv.y, nv.z).dot(inv * d), 0.0);
        }
      }
    }
  }
}

TEST(Visualization, CullingKeepsTheGaussiansWithMostPoints) {
  const auto map = sampleMap();
  mrpt_ndtom::TRenderOptions options;
  options.subdivisions = 0;
  options.max_ellipsoids = 2;
  mrpt::opengl::CSetOfObjects objs;
  mrpt_ndtom::buildNdtVisualization(map->ndtMap(), options, objs);
  const auto mesh = meshOf(objs);
  ASSERT_TRUE(mesh);
  ASSERT_EQ(mesh->getTrianglesCount(), 2u * 8u);
  std::vector<uint32_t> counts;
  map->ndtMap().forEachGaussian([&](const ndtom::Gaussian& g) { counts.push_back(g.n); });
  std::sort(counts.rbegin(), counts.rend());
  ASSERT_GE(counts.size(), 3u);
  // The drawn ellipsoids hold the two largest counts: the 30-point blob is left out.
  const Eigen::Vector3d small_blob(-2.25, 1.25, 0.75);
  for (size_t t = 0; t < mesh->getTrianglesCount(); ++t) {
    mrpt::opengl::TTriangle tri;
    mesh->getTriangle(t, tri);
    const auto& p = tri.vertices[0].xyzrgba.pt;
    EXPECT_GT((Vector3d(p.x, p.y, p.z) - small_blob).norm(), 0.5);
  }
}

TEST(Visualization, HonoursEnableSaveAs3DObjectAndFreeCells) {
  auto map = sampleMap();
  mrpt::opengl::CSetOfObjects drawn;
  map->getVisualizationInto(drawn);
  EXPECT_TRUE(meshOf(drawn));
  EXPECT_FALSE(drawn.getByName("ndtom_free_cells"));

  map->renderOptions.show_free_cells = true;
  mrpt::opengl::CSetOfObjects with_free;
  map->getVisualizationInto(with_free);
  const auto free_cells = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(
      with_free.getByName("ndtom_free_cells"));
  ASSERT_TRUE(free_cells);
  size_t free_count = 0;
  map->ndtMap().forEachCell([&](const ndtom::CellView& c) { free_count += c.logodds < 0; });
  EXPECT_GT(free_count, 0u);
  EXPECT_EQ(free_cells->size(), free_count);

  map->genericMapParams.enableSaveAs3DObject = false;
  mrpt::opengl::CSetOfObjects nothing;
  map->getVisualizationInto(nothing);
  EXPECT_EQ(nothing.size(), 0u);

  mrpt_ndtom::TRenderOptions bad;
  bad.quantiles = 0;
  EXPECT_THROW(mrpt_ndtom::buildNdtVisualization(map->ndtMap(), bad, nothing),
               std::invalid_argument);
}

TEST(Visualization, SaveRepresentationWritesMapAndScene) {
  const auto map = sampleMap();
  const std::string prefix = mrpt::system::getTempFileName() + "_ndt";
  map->saveMetricMapRepresentationToFile(prefix);

  EXPECT_EQ(ndtom::encodeMap(ndtom::loadMap(prefix + ".ndtom")), ndtom::encodeMap(map->ndtMap()));
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(prefix + ".3Dscene"));
  const auto mesh = scene.getByClass<mrpt::opengl::CSetOfTriangles>();
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->getTrianglesCount(),
            map->ndtMap().numGaussians() *
                mrpt_ndtom::trianglesPerEllipsoid(map->renderOptions.subdivisions));
  std::remove((prefix + ".ndtom").c_str());
  std::remove((prefix + ".3Dscene").c_str());
}

TEST(Visualization, RendersOffscreen) {
  // The saved scene drawn by MRPT's own offscreen renderer (EGL, no display): the ellipsoids
  // cover part of the picture, coloured by height.
  const auto map = sampleMap();
  mrpt::opengl::COpenGLScene scene;
  auto objects = mrpt::opengl::CSetOfObjects::Create();
  map->getVisualizationInto(*objects);
  scene.insert(objects);
  // CFBORender (MRPT 2.5.8) draws from its own camera, not the viewport's.
  mrpt::opengl::CCamera camera;
  camera.setPointingAt(0.5f, 0.5f, 0.2f);  // the floor's four flat Gaussians
  camera.setZoomDistance(3);
  camera.setElevationDegrees(35);
  camera.setAzimuthDegrees(-60);

  mrpt::img::CImage image;
  try {
    mrpt::opengl::CFBORender renderer(mrpt::opengl::CFBORender::Parameters(320, 240));
    renderer.setCamera(scene, camera);
    renderer.render_RGB(scene, image);
  } catch (const std::exception& e) {
    GTEST_SKIP() << "no offscreen OpenGL here: " << e.what();
  }
  ASSERT_EQ(image.getWidth(), 320u);
  if (const char* out = std::getenv("NDTOM_RENDER_OUT")) image.saveToFile(out);
  const auto background = pixel(image, 0, 0);  // a corner: no map there
  size_t drawn = 0;
  for (unsigned y = 0; y < 240; ++y)
    for (unsigned x = 0; x < 320; ++x) drawn += pixel(image, x, y) != background;
  EXPECT_GT(drawn, 320u * 240u / 100) << "at least 1% of the pixels show the map";

  // An empty map draws nothing but the background.
  mrpt::opengl::COpenGLScene empty_scene;
  mrpt::img::CImage empty_image;
  mrpt::opengl::CFBORender empty_renderer(mrpt::opengl::CFBORender::Parameters(320, 240));
  empty_renderer.setCamera(empty_scene, camera);
  empty_renderer.render_RGB(empty_scene, empty_image);
  size_t empty_drawn = 0;
  for (unsigned y = 0; y < 240; ++y)
    for (unsigned x = 0; x < 320; ++x) empty_drawn += pixel(empty_image, x, y) != background;
  EXPECT_EQ(empty_drawn, 0u);
}

TEST(Visualization, RecursiveNdtMapsDrawEveryGaussian) {
  // Without occupancy there are no log-odds: every cell with a Gaussian is occupied (the one
  // rule of ndtom/map/map_queries.h), and nothing is free.
  auto map = CNDTOccupancyMap::Create(0.5);
  map->insertionOptions.occupancy.enabled = false;
  map->renderOptions.show_free_cells = true;
  const auto occupied = sampleMap();
  std::vector<Vector3d> points;
  occupied->ndtMap().forEachGaussian([&](const ndtom::Gaussian& g) { points.push_back(g.mean); });
  for (int copy = 0; copy < 3; ++copy) map->insertPoints(points, Vector3d(0.5, 0.5, 5.0));
  ASSERT_GT(map->ndtMap().numGaussians(), 3u);
  mrpt::opengl::CSetOfObjects objs;
  map->getVisualizationInto(objs);
  const auto mesh = meshOf(objs);
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->getTrianglesCount(),
            map->ndtMap().numGaussians() * mrpt_ndtom::trianglesPerEllipsoid(1));
  const auto free = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(
      objs.getByName("ndtom_free_cells"));
  ASSERT_TRUE(free);
  EXPECT_EQ(free->size(), 0u);
}

// Issue #38: --ellipsoid-detail 4 on a 27k-Gaussian map reserved ~7 GB of triangles. The
// detail is lowered until the scene fits kMaxSceneTriangles, and no further.
TEST(Visualization, DetailIsLoweredToTheTriangleBudget) {
  using mrpt_ndtom::kMaxSceneTriangles;
  using mrpt_ndtom::subdivisionsWithinBudget;
  using mrpt_ndtom::trianglesPerEllipsoid;
  for (const size_t drawn : {size_t(1), size_t(500), size_t(1500), size_t(8192), size_t(40000),
                             kMaxSceneTriangles / 8, kMaxSceneTriangles})
    for (uint32_t requested = 0; requested <= 4; ++requested) {
      const uint32_t s = subdivisionsWithinBudget(drawn, requested);
      EXPECT_LE(s, requested);
      if (s > 0) {
        EXPECT_LE(drawn * trianglesPerEllipsoid(s), kMaxSceneTriangles) << drawn;
      }
      if (s < requested) {  // lowered only as far as needed
        EXPECT_GT(drawn * trianglesPerEllipsoid(s + 1), kMaxSceneTriangles) << drawn;
      }
    }
  // A map of ~1000 Gaussians: detail 4 would be 2 million triangles.
  auto map = CNDTOccupancyMap::Create(0.5);
  std::vector<Vector3d> points;
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 32; ++j)
      for (int k = 0; k < 3; ++k)
        points.emplace_back(0.5 * i + 0.1 + 0.1 * k, 0.5 * j + 0.25, 0.1 * k + 0.1);
  map->insertPoints(points, Vector3d(8, 8, 5));
  const size_t n = map->ndtMap().numGaussians();
  ASSERT_GT(n * trianglesPerEllipsoid(4), kMaxSceneTriangles);
  mrpt_ndtom::TRenderOptions options;
  options.subdivisions = 4;
  mrpt::opengl::CSetOfObjects objs;
  mrpt_ndtom::buildNdtVisualization(map->ndtMap(), options, objs);
  const auto mesh = meshOf(objs);
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->getTrianglesCount(), n * trianglesPerEllipsoid(subdivisionsWithinBudget(n, 4)));
  EXPECT_LE(mesh->getTrianglesCount(), kMaxSceneTriangles);
  EXPECT_LT(subdivisionsWithinBudget(n, 4), 4u);
}
