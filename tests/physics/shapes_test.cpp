// Spheres, capsules and height maps: the contact on hard cases (the centre, the surface, a
// capsule's caps and the junction with its cylinder, a height map's cells), and the scene
// keys that make them and the mesh files (binary STL, ASCII STL, OBJ), with the errors a
// user can meet naming the file, the line and the fix.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

#include <png.h>

#include "tests/physics/models.h"
#include "tests/support/refusal.h"

namespace enact::physics {
namespace {

constexpr double kStiffness_n_per_m = 6000.0;

using models::Probe;
using models::probe;

void expect_near(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Sphere, CentreSurfaceAndJustInside) {
  Model m;
  const Vec3 c{0.01, -0.02, 0.03};
  models::add_capsule(m, "ball", c, c, 0.005, {0, 0, 1});
  // the centre: the full radius deep, pushed along the sphere's axis normal (up)
  const Probe centre = probe(m, 0, c);
  EXPECT_EQ(centre.depth_m, 0.005);
  EXPECT_EQ(centre.normal, (Vec3{0, 0, 1}));
  // on the surface and just outside: no contact
  const Vec3 out = models::unit({1, 2, -2});
  EXPECT_NEAR(probe(m, 0, c + out * 0.005).depth_m, 0.0, 1e-15);
  EXPECT_EQ(probe(m, 0, c + out * 0.0050001).depth_m, 0.0);
  // just inside: radial, at the depth
  const Probe inside = probe(m, 0, c + out * (0.005 - 1e-7));
  EXPECT_NEAR(inside.depth_m, 1e-7, 1e-15);
  expect_near(inside.normal, out, 1e-12);
  const Probe half = probe(m, 0, c + out * 0.0025);
  EXPECT_NEAR(half.depth_m, 0.0025, 1e-15);
  expect_near(half.normal, out, 1e-12);
}

TEST(Capsule, CylinderCapsAxisAndTheirJunction) {
  Model m;
  const Vec3 a{0, 0, 0.01}, b{0.02, 0, 0.01};
  models::add_capsule(m, "rod", a, b, 0.004, {0, 1, 0});
  // the cylinder: pushed straight away from the axis
  const Probe side = probe(m, 0, {0.012, 0.0, 0.013});
  EXPECT_NEAR(side.depth_m, 0.001, 1e-15);
  expect_near(side.normal, {0, 0, 1}, 1e-15);
  // the caps: away from the end points
  const Vec3 out = models::unit({-1, 1, 1});
  const Probe cap = probe(m, 0, a + out * 0.003);
  EXPECT_NEAR(cap.depth_m, 0.001, 1e-15);
  expect_near(cap.normal, out, 1e-12);
  const Probe far_cap = probe(m, 0, b + Vec3{0.0039, 0, 0});
  EXPECT_NEAR(far_cap.depth_m, 0.0001, 1e-15);
  expect_near(far_cap.normal, {1, 0, 0}, 1e-15);
  // beyond the cap, in line with the cylinder's surface: outside
  EXPECT_EQ(probe(m, 0, b + Vec3{0.0001, 0, 0.004}).depth_m, 0.0);
  // on the axis: the full radius, along the capsule's axis normal
  const Probe axis = probe(m, 0, {0.005, 0, 0.01});  // exactly on it (a quarter of the way)
  EXPECT_EQ(axis.depth_m, 0.004);
  EXPECT_EQ(axis.normal, (Vec3{0, 1, 0}));
  // across the junction of the cylinder and a cap, 1 mm inside: the force never jumps by more
  // than the stiffness times the step's travel
  Vec3 last;
  const int n = 4000;
  for (int i = 0; i <= n; ++i) {
    const Vec3 x{0.017 + 0.006 * i / n, 0.0, 0.013 - 0.0005 * i / n};
    const Probe p = probe(m, 0, x);
    const Vec3 force = p.normal * (kStiffness_n_per_m * p.depth_m);
    if (i > 0) {
      EXPECT_LE(norm(force - last), kStiffness_n_per_m * norm(Vec3{0.006, 0, -0.0005}) / n + 1e-9) << x.x;
    }
    EXPECT_GT(p.depth_m, 0.0) << x.x;
    last = force;
  }
}

TEST(Capsule, PairCullingSkipsItOnlyAwayFromIt) {
  Model m;
  models::add_capsule(m, "rod", {0, 0, 0.01}, {0.02, 0, 0.01}, 0.004, {0, 1, 0});
  EXPECT_TRUE(apart(m, m.objects[0], {0.01, 0, 0.0201}, 0.006));
  EXPECT_FALSE(apart(m, m.objects[0], {0.01, 0, 0.0199}, 0.006));
  EXPECT_TRUE(apart(m, m.objects[0], {0.0301, 0, 0.01}, 0.006));
}

// ---- scene files ----

// a scene with one object written by `object` (YAML lines under objects:), in `dir`
Model scene_with(const test::TempDir& dir, const std::string& object) {
  test::write_file(dir.file("scene.yaml"), "masses:\n  - {name: m, mass_kg: 0.01, position_m: [0, 0, 0.05]}\nobjects:\n" + object);
  return load_scene(dir.file("scene.yaml"));
}

// the unit cube's corners and its 6 faces as quads, counter-clockwise seen from outside
const double kCorners[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
const int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}};

std::string cube_obj(int faces = 6) {
  std::string s = "# a cube\n";
  for (const auto& c : kCorners) s += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (int f = 0; f < faces; ++f) s += "f " + std::to_string(kQuads[f][0] + 1) + "/1 " + std::to_string(kQuads[f][1] + 1) + " " + std::to_string(kQuads[f][2] + 1) + "//3 " + std::to_string(kQuads[f][3] + 1) + "\n";
  return s;
}

std::string cube_ascii_stl() {
  std::string s = "solid cube\n";
  for (const auto& q : kQuads) {
    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      s += "  facet normal 0 0 0\n    outer loop\n";
      for (int k : t) s += "      vertex " + std::to_string(kCorners[k][0]) + " " + std::to_string(kCorners[k][1]) + " " + std::to_string(kCorners[k][2]) + "\n";
      s += "    endloop\n  endfacet\n";
    }
  }
  return s + "endsolid cube\n";
}

std::string cube_binary_stl() {
  std::string s(80, ' ');
  const std::uint32_t count = 12;
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& q : kQuads) {
    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      float floats[12] = {};
      for (int k = 0; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) floats[3 + 3 * k + a] = static_cast<float>(kCorners[t[k]][a]);
      }
      s.append(reinterpret_cast<const char*>(floats), sizeof floats);
      s.append(2, '\0');
    }
  }
  return s;
}

TEST(SceneObjects, AMeshLoadsFromBinaryStlAsciiStlAndObjScaledAndPlaced) {
  const test::TempDir dir;
  test::write_file(dir.file("cube.obj"), cube_obj());
  test::write_file(dir.file("cube_ascii.stl"), cube_ascii_stl());
  test::write_file(dir.file("cube_binary.stl"), cube_binary_stl());
  for (const char* file : {"cube.obj", "cube_ascii.stl", "cube_binary.stl"}) {
    // a 10 mm cube (a file in mm), its origin at (0.01, 0, 0), turned 90 degrees about z
    const Model m = scene_with(dir, std::string("  - {name: cube, type: mesh, file: ") + file +
                                        ", scale: 0.01, center_m: [0.01, 0, 0], rpy_deg: [0, 0, 90]}\n");
    ASSERT_EQ(m.objects[0].type, ObjectType::mesh) << file;
    const Mesh& mesh = m.meshes[m.objects[0].mesh];
    EXPECT_EQ(mesh.triangles.size(), 12u) << file;
    EXPECT_EQ(mesh.vertices_m.size(), 8u) << file;
    expect_near(mesh.nodes[0].low_m, {0.0, 0.0, 0.0}, 1e-12);
    expect_near(mesh.nodes[0].high_m, {0.01, 0.01, 0.01}, 1e-12);
    const Probe p = probe(m, 0, {0.005, 0.005, 0.009});
    EXPECT_NEAR(p.depth_m, 0.001, 1e-12) << file;
    expect_near(p.normal, {0, 0, 1}, 1e-12);
  }
}

TEST(SceneObjects, AnOpenMeshIsRefusedNamingTheFileTheLineAndTheFix) {
  const test::TempDir dir;
  test::write_file(dir.file("open.obj"), cube_obj(5));
  const std::string error = test::error_of([&] { scene_with(dir, "  - {name: box, type: mesh, file: open.obj}\n"); });
  EXPECT_NE(error.find("open.obj:"), std::string::npos) << error;
  EXPECT_NE(error.find("the mesh is open"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: close the mesh (a contact needs an inside"), std::string::npos) << error;
  // a face wound the other way
  std::string flipped = cube_obj();
  flipped.replace(flipped.rfind("f "), std::string::npos, "f 3 4//3 8 7/1\n");
  const std::string wound = test::error_of([&] {
    test::write_file(dir.file("flipped.obj"), flipped);
    scene_with(dir, "  - {name: box, type: mesh, file: flipped.obj}\n");
  });
  EXPECT_NE(wound.find("flipped.obj:15:"), std::string::npos) << wound;
  EXPECT_NE(wound.find("runs the same way"), std::string::npos) << wound;
  // a face naming a vertex that is not there
  const std::string missing = test::error_of([&] {
    test::write_file(dir.file("missing.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    scene_with(dir, "  - {name: box, type: mesh, file: missing.obj}\n");
  });
  EXPECT_NE(missing.find("missing.obj:4: face corner '4'"), std::string::npos) << missing;
  // no such file: the scene's line
  const std::string absent = test::error_of([&] { scene_with(dir, "  - {name: box, type: mesh, file: nowhere.stl}\n"); });
  EXPECT_NE(absent.find("scene.yaml:4:"), std::string::npos) << absent;
  EXPECT_NE(absent.find("there is no file"), std::string::npos) << absent;
}

TEST(SceneObjects, SpheresAndCapsulesLoad) {
  const test::TempDir dir;
  const Model m = scene_with(dir, "  - {name: ball, type: sphere, center_m: [0, 0, 0.01], radius_m: 0.005}\n"
                                  "  - {name: rod, type: capsule, from_m: [0, 0, 0], to_m: [0, 0, 0.02], radius_m: 0.002}\n");
  EXPECT_EQ(m.objects[0].type, ObjectType::capsule);
  EXPECT_EQ(m.objects[0].shape, "sphere");
  EXPECT_NEAR(probe(m, 0, {0.004, 0, 0.01}).depth_m, 0.001, 1e-15);
  // a vertical capsule's axis normal is horizontal
  EXPECT_EQ(probe(m, 1, {0, 0, 0.01}).depth_m, 0.002);
  EXPECT_EQ(probe(m, 1, {0, 0, 0.01}).normal.z, 0.0);
  const std::string error = test::error_of([&] { scene_with(dir, "  - {name: rod, type: capsule, from_m: [0, 0, 0], to_m: [0, 0, 0], radius_m: 0.002}\n"); });
  EXPECT_NE(error.find("scene.yaml:4:"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: give two different ends"), std::string::npos) << error;
}

TEST(SceneObjects, AHeightMapIsTwoTrianglesPerCellOverItsGrid) {
  const test::TempDir dir;
  // 3 x 3 heights, 10 mm cells: flat at 4 mm but the far-left corner at 8 mm
  test::write_file(dir.file("heights.csv"), "0.008, 0.004, 0.004\n0.004,0.004,0.004\n0.004,0.004,0.004\n");
  const Model m = scene_with(dir, "  - {name: ground, type: heightmap, file: heights.csv, cell_m: 0.01, center_m: [0, 0, 0.001], bottom_z_m: 0}\n");
  ASSERT_EQ(m.objects[0].shape, "heightmap");
  const Mesh& mesh = m.meshes[m.objects[0].mesh];
  EXPECT_EQ(mesh.triangles.size(), 2u * 4u * 2u + 2u * 8u);  // 2 a cell on top and on the base, 2 a wall
  // the flat cells: 5 mm high (center_m z + 4 mm), the depth straight below it
  const Probe flat = probe(m, 0, {0.006, -0.004, 0.0045});
  EXPECT_NEAR(flat.depth_m, 0.0005, 1e-12);
  expect_near(flat.normal, {0, 0, 1}, 1e-12);
  EXPECT_EQ(probe(m, 0, {0.006, -0.004, 0.0051}).depth_m, 0.0);
  // the far-left cell's triangle with its north-east corner (row 0 is +y, column 0 is -x):
  // rising 4 mm over 10 mm towards the raised corner at -x; below it along its normal
  const Vec3 n = models::unit({0.004, 0.0, 0.01});
  const Vec3 on_slope{-0.002, 0.008, 0.005 + 0.004 * 0.2};
  const Probe slope = probe(m, 0, on_slope - n * 0.0002);
  EXPECT_NEAR(slope.depth_m, 0.0002, 1e-12);
  expect_near(slope.normal, n, 1e-12);
  // a row of another length names the CSV's line
  test::write_file(dir.file("bad.csv"), "0.001,0.002\n0.001\n");
  const std::string error = test::error_of([&] { scene_with(dir, "  - {name: g, type: heightmap, file: bad.csv, cell_m: 0.01}\n"); });
  EXPECT_NE(error.find("bad.csv:2: this row has 1 heights, the first had 2"), std::string::npos) << error;
  EXPECT_NE(error.find("fix:"), std::string::npos) << error;
}

// a grayscale PNG of w x h pixels, 16 bits (or 8)
void write_png(const std::string& path, int w, int h, const std::vector<std::uint16_t>& values, bool sixteen_bits = true) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(w);
  image.height = static_cast<png_uint_32>(h);
  image.format = sixteen_bits ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_GRAY;
  std::vector<std::uint8_t> bytes(values.begin(), values.end());
  const void* data = sixteen_bits ? static_cast<const void*>(values.data()) : static_cast<const void*>(bytes.data());
  ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, data, 0, nullptr)) << image.message;
}

TEST(SceneObjects, AHeightMapReadsA16BitPng) {
  const test::TempDir dir;
  // 3 x 2 pixels: the top row (+y) at full scale (8 mm), the bottom row at a quarter
  write_png(dir.file("h.png"), 3, 2, {65535, 65535, 65535, 16384, 16384, 16384});
  const Model m = scene_with(dir, "  - {name: g, type: heightmap, file: h.png, cell_m: 0.01, max_height_m: 0.008}\n");
  // the middle, under the slope from 2 mm (y = -5 mm) up to 8 mm (y = +5 mm): 5 mm high at y = 0
  const double at_middle_m = 0.008 * 16384.0 / 65535.0 + 0.5 * (0.008 - 0.008 * 16384.0 / 65535.0);
  const Vec3 n = models::unit({0.0, -(0.008 - 0.008 * 16384.0 / 65535.0), 0.01});
  const Probe p = probe(m, 0, Vec3{0.002, 0.0, at_middle_m} - n * 0.0003);
  EXPECT_NEAR(p.depth_m, 0.0003, 1e-12);
  expect_near(p.normal, n, 1e-12);
  // 8 bits, and a PNG without its scale: refused with the fix
  write_png(dir.file("h8.png"), 3, 2, {255, 255, 255, 64, 64, 64}, false);
  const std::string eight = test::error_of([&] { scene_with(dir, "  - {name: g, type: heightmap, file: h8.png, cell_m: 0.01, max_height_m: 0.008}\n"); });
  EXPECT_NE(eight.find("h8.png: the PNG is not 16-bit grayscale\n  fix: save it as 16-bit grayscale"), std::string::npos) << eight;
  const std::string unscaled = test::error_of([&] { scene_with(dir, "  - {name: g, type: heightmap, file: h.png, cell_m: 0.01}\n"); });
  EXPECT_NE(unscaled.find("scene.yaml:4:"), std::string::npos) << unscaled;
  EXPECT_NE(unscaled.find("fix: add max_height_m"), std::string::npos) << unscaled;
}

// a task on an object that is not a path names the line to follow, its top and its width;
// a path object gives its own; each refusal names the line and the fix
TEST(SceneObjects, ATaskOnAnyObjectNamesItsLineTopAndWidth) {
  test::TempDir dir;
  const std::string ball = "  - {name: ball, type: sphere, center_m: [0, 0, 0], radius_m: 0.01}\n";
  const std::string bridge = "  - {name: bridge, type: path, points_m: [[0, 0], [0.02, 0]], width_m: 0.01, top_z_m: 0.01}\n";
  const Model m = scene_with(dir, ball + "task: {surface: ball, points_m: [[-0.005, 0], [0.005, 0]], top_z_m: 0.01, width_m: 0.004}\n");
  EXPECT_EQ(m.task_surface, "ball");
  ASSERT_EQ(m.task_path.centerline_m.size(), 2u);
  EXPECT_EQ(m.task_path.centerline_m[1].x, 0.005);
  EXPECT_EQ(m.task_path.top_z_m, 0.01);
  EXPECT_EQ(m.task_path.width_m, 0.004);
  const Model p = scene_with(dir, bridge + "task: {surface: bridge}\n");
  EXPECT_EQ(p.task_path.centerline_m.size(), 2u);
  EXPECT_EQ(p.task_path.width_m, 0.01);

  const std::string missing = test::error_of([&] { scene_with(dir, ball + "task: {surface: ball, top_z_m: 0.01, width_m: 0.004}\n"); });
  EXPECT_NE(missing.find("scene.yaml:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("needs points_m"), std::string::npos) << missing;
  EXPECT_NE(missing.find("fix:"), std::string::npos) << missing;
  const std::string own = test::error_of([&] { scene_with(dir, bridge + "task: {surface: bridge, width_m: 0.004}\n"); });
  EXPECT_NE(own.find("gives the task its own centreline"), std::string::npos) << own;
  const std::string plane = test::error_of([&] { scene_with(dir, "  - {name: floor, type: plane, point_m: [0, 0, 0], normal: [0, 0, 1]}\ntask: {surface: floor}\n"); });
  EXPECT_NE(plane.find("a plane cannot be the task's surface"), std::string::npos) << plane;
  const std::string misspelt = test::error_of([&] { scene_with(dir, ball + "task: {surface: bal}\n"); });
  EXPECT_NE(misspelt.find("did you mean ball"), std::string::npos) << misspelt;
  const std::string repeated = test::error_of([&] { scene_with(dir, ball + "task: {surface: ball, points_m: [[0, 0], [0, 0]], top_z_m: 0.01, width_m: 0.004}\n"); });
  EXPECT_NE(repeated.find("two consecutive path points are equal"), std::string::npos) << repeated;
}

TEST(SceneObjects, TheShippedShapesScenePushesOutOfEachOfItsObjects) {
  const Model m = load_scene(test::source_path("launch/scenes/shapes.yaml"));
  // a point inside each object (and above the floor), and one above all of them
  const std::pair<const char*, Vec3> inside[] = {{"ridges", {-0.014, 0.013, 0.001}},
                                                 {"wedge", {0.010, 0.013, 0.001}},
                                                 {"ball", {-0.013, -0.013, 0.005}},
                                                 {"rod", {0.014, -0.013, 0.004}}};
  for (const auto& [name, x] : inside) {
    const int o = m.find_object(name);
    ASSERT_GE(o, 0) << name;
    EXPECT_GT(probe(m, o, x).depth_m, 0.0) << name;
    EXPECT_EQ(probe(m, o, {0, 0, 0.02}).depth_m, 0.0) << name;
  }
  EXPECT_EQ(m.meshes[m.objects[m.find_object("wedge")].mesh].triangles.size(), 8u);
}

}  // namespace
}  // namespace enact::physics
