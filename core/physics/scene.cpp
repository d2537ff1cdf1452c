#include "core/physics/scene.h"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "core/config/share.h"
#include "core/config/suggest.h"
#include "core/config/yaml.h"
#include "core/physics/mesh_file.h"

namespace enact::physics {
namespace {

using config::Map;

Vec3 vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

constexpr double kDegree = std::numbers::pi / 180.0;

struct Loader {
  std::string file;
  Model model;

  // a name must be new: points and objects share one namespace
  void check_new_name(const Map& m, const std::string& name) {
    if (name.empty()) m.fail("name", "a name must not be empty", "give every element a unique name");
    if (model.find_point(name) >= 0 || model.find_object(name) >= 0) {
      m.fail("name", "the name '" + name + "' is used twice", "give every mass, fixed point, body and object its own name");
    }
  }

  void masses(const Map& scene) {
    for (const auto& n : scene.list("masses")) {
      Map m(n, file, "mass", {"name", "mass_kg", "position_m", "velocity_m_per_s"});
      Point p;
      p.name = m.text("name");
      check_new_name(m, p.name);
      p.kind = PointKind::dynamic;
      if (!m.has("mass_kg")) m.fail("mass_kg", "mass '" + p.name + "' has no mass_kg", "add mass_kg: 0.01 (kg, > 0)");
      p.mass_kg = m.positive("mass_kg");
      p.position_m = vec(m.vec3("position_m"));
      p.velocity_m_per_s = vec(m.vec3("velocity_m_per_s", {0, 0, 0}));
      p.line = m.line();
      model.points.push_back(p);
    }
    for (const auto& n : scene.list("fixed")) {
      Map m(n, file, "fixed point", {"name", "position_m"});
      Point p;
      p.name = m.text("name");
      check_new_name(m, p.name);
      p.kind = PointKind::fixed;
      p.position_m = vec(m.vec3("position_m"));
      p.line = m.line();
      model.points.push_back(p);
    }
  }

  void body(const Map& scene) {
    if (!scene.has("body")) return;
    Map b(scene.get("body"), file, "body", {"name", "position_m", "grid", "deformable"});
    Proxy proxy;
    proxy.name = b.text("name", "finger");
    check_new_name(b, proxy.name);
    proxy.line = b.line();
    int rows = 0, cols = 0;
    double pitch = 0.0;
    if (b.has("grid")) {
      Map g(b.get("grid"), file, "body.grid", {"rows", "cols", "pitch_m"});
      rows = g.integer("rows", 4, 1, 8);
      cols = g.integer("cols", 4, 1, 8);
      if (rows * cols > 32) g.fail("rows", "a grid has at most 32 masses (pins)", "use rows x cols <= 32");
      pitch = g.positive("pitch_m", 0.00245);
    }
    const Vec3 centre = vec(b.vec3("position_m"));
    Point p;
    p.name = proxy.name;
    p.kind = PointKind::kinematic;
    p.position_m = centre;
    p.proxy = static_cast<int>(model.proxies.size());
    p.line = proxy.line;
    proxy.point = static_cast<int>(model.points.size());
    model.points.push_back(p);
    proxy.first_body = static_cast<int>(model.points.size());
    proxy.rows = rows;
    proxy.cols = cols;
    proxy.pitch_m = pitch;
    // row 0 is the far row (+y), column 0 the left column (-x); the grid is centred on the proxy
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        Point g = p;
        g.name = grid_point_name(proxy.name, r, c);
        g.offset_m = {(c - (cols - 1) / 2.0) * pitch, ((rows - 1) / 2.0 - r) * pitch, 0.0};
        g.position_m = centre + g.offset_m;
        model.points.push_back(g);
      }
    }
    model.proxies.push_back(proxy);
    if (b.has("deformable")) deformable(Map(b.get("deformable"), file, "body.deformable", {"mass_kg", "proxy_link", "grid_link"}));
  }

  // body.deformable: every grid mass dynamic, of mass_kg, tied to the proxy and its neighbours
  void deformable(const Map& d) {
    const Proxy& proxy = model.proxies.back();
    DeformableBody body;
    body.line = d.line();
    if (proxy.rows * proxy.cols == 0) d.fail("mass_kg", "a deformable body needs grid masses", "add grid: {rows: 4, cols: 4, pitch_m: 0.00245} to the body");
    if (!d.has("mass_kg")) d.fail("mass_kg", "a deformable body needs the mass of each grid mass", "add mass_kg: 0.0005 (kg, > 0)");
    body.mass_kg = d.positive("mass_kg");
    if (!d.has("proxy_link")) {
      d.fail("proxy_link", "a deformable body's masses need a link to the device proxy", "add proxy_link: {stiffness_n_per_m: 2000, damping_n_s_per_m: 0.3}");
    }
    const Map proxy_link(d.get("proxy_link"), file, "body.deformable.proxy_link", {"stiffness_n_per_m", "damping_n_s_per_m"});
    if (!proxy_link.has("stiffness_n_per_m")) proxy_link.fail("stiffness_n_per_m", "a proxy link needs a stiffness", "add stiffness_n_per_m: 2000 (N/m, > 0)");
    body.proxy_stiffness_n_per_m = proxy_link.positive("stiffness_n_per_m");
    body.proxy_damping_n_s_per_m = proxy_link.positive("damping_n_s_per_m", 0.0, true);
    if (d.has("grid_link")) {
      const Map grid_link(d.get("grid_link"), file, "body.deformable.grid_link", {"stiffness_n_per_m", "damping_n_s_per_m"});
      body.grid_stiffness_n_per_m = grid_link.positive("stiffness_n_per_m", 0.0, true);
      body.grid_damping_n_s_per_m = grid_link.positive("damping_n_s_per_m", 0.0, true);
    }
    model.make_deformable(static_cast<int>(model.proxies.size()) - 1, body);
  }

  int point(const Map& m, const char* key) {
    const std::string name = m.text(key);
    const int i = model.find_point(name);
    if (i < 0) m.fail(key, "link end '" + name + "' is not a mass, fixed point or body mass", "name an element defined in masses:, fixed: or body:");
    return i;
  }

  void links(const Map& scene) {
    int index = 0;
    for (const auto& n : scene.list("links")) {
      Map m(n, file, "link", {"name", "type", "a", "b", "stiffness_n_per_m", "damping_n_s_per_m", "rest_length_m",
                              "threshold_m", "cubic_n_per_m3", "max_stiffness_n_per_m"});
      Link l;
      l.name = m.text("name", "link" + std::to_string(index++));
      const std::string type = m.text("type");
      if (type == "spring") l.type = LinkType::spring;
      else if (type == "damper") l.type = LinkType::damper;
      else if (type == "spring_damper") l.type = LinkType::spring_damper;
      else if (type == "contact") l.type = LinkType::contact;
      else if (type == "nonlinear_spring") l.type = LinkType::nonlinear_spring;
      else m.fail("type", "unknown link type '" + type + "'", "use spring, damper, spring_damper, contact or nonlinear_spring");
      l.a = point(m, "a");
      l.b = point(m, "b");
      if (l.a == l.b) m.fail("b", "link '" + l.name + "' joins a point to itself", "link two different points");
      const bool stiff = l.type != LinkType::damper;
      const bool damped = l.type == LinkType::damper || l.type == LinkType::spring_damper || l.type == LinkType::contact;
      if (stiff && !m.has("stiffness_n_per_m")) m.fail("stiffness_n_per_m", "link '" + l.name + "' needs stiffness_n_per_m", "add stiffness_n_per_m: 100 (N/m, >= 0)");
      l.stiffness_n_per_m = m.positive("stiffness_n_per_m", 0.0, true);
      l.damping_n_s_per_m = damped ? m.positive("damping_n_s_per_m", 0.0, true) : 0.0;
      if (!damped && m.has("damping_n_s_per_m")) m.fail("damping_n_s_per_m", "a " + type + " has no damping", "use type: spring_damper, or remove damping_n_s_per_m");
      l.rest_length_m = m.positive("rest_length_m", 0.0, true);
      if (l.type == LinkType::contact) {
        if (!m.has("threshold_m")) m.fail("threshold_m", "contact link '" + l.name + "' needs threshold_m", "add threshold_m: 0.002 (m): the distance below which it pushes");
        l.threshold_m = m.positive("threshold_m");
      }
      if (l.type == LinkType::nonlinear_spring) {
        l.cubic_n_per_m3 = m.positive("cubic_n_per_m3", 0.0, true);
        if (!m.has("max_stiffness_n_per_m")) m.fail("max_stiffness_n_per_m", "nonlinear spring '" + l.name + "' needs max_stiffness_n_per_m", "add the largest stiffness (N/m) it may reach");
        l.max_stiffness_n_per_m = m.positive("max_stiffness_n_per_m");
        if (l.max_stiffness_n_per_m < l.stiffness_n_per_m) m.fail("max_stiffness_n_per_m", "max_stiffness_n_per_m is below stiffness_n_per_m", "make max_stiffness_n_per_m >= stiffness_n_per_m");
        l.clip_elongation_m = l.cubic_n_per_m3 > 0.0
                                  ? std::sqrt((l.max_stiffness_n_per_m - l.stiffness_n_per_m) / (3.0 * l.cubic_n_per_m3))
                                  : std::numeric_limits<double>::infinity();
      }
      l.line = m.line();
      model.links.push_back(l);
    }
  }

  Box box(const Map& m) {
    Box b;
    b.center_m = vec(m.vec3("center_m"));
    b.half_extents_m = vec(m.vec3("half_extents_m"));
    if (b.half_extents_m.x <= 0 || b.half_extents_m.y <= 0 || b.half_extents_m.z <= 0) {
      m.fail("half_extents_m", "half_extents_m must all be > 0", "give the half sizes along the box's x, y and z (m)");
    }
    const auto rpy = m.vec3("rpy_deg", {0, 0, 0});
    b.rotation = rotation_rpy(rpy[0] * kDegree, rpy[1] * kDegree, rpy[2] * kDegree);
    return b;
  }

  // a path: one box per segment, each extended by half the width at both ends so that
  // turns are filled; the top surface is flat and the walls vertical
  // a centreline from points_m ([[x, y], ...], at least 2, none repeated) at height top (m)
  std::vector<Vec3> centreline(const Map& m, double top, const char* what) const {
    const YAML::Node pts = m.get("points_m");
    if (!pts.IsSequence() || pts.size() < 2) m.fail("points_m", std::string(what) + " needs at least 2 points", "write points_m: [[x, y], [x, y], ...] (m)");
    std::vector<Vec3> line;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto xy = config::numbers(file, pts[i], 2, "path point");
      line.push_back({xy[0], xy[1], top});
      if (i > 0 && line[i].x == line[i - 1].x && line[i].y == line[i - 1].y) config::fail(file, pts[i], "two consecutive path points are equal", "remove the repeated point");
    }
    return line;
  }

  void path(const Map& m, Object& o) {
    const double width = m.positive("width_m");
    const double bottom = m.number("bottom_z_m", 0.0);
    const double top = m.number("top_z_m");
    if (top <= bottom) m.fail("top_z_m", "top_z_m must be above bottom_z_m", "give the height of the top surface (m)");
    o.is_path = true;
    o.path.width_m = width;
    o.path.bottom_z_m = bottom;
    o.path.top_z_m = top;
    o.path.centerline_m = centreline(m, top, "a path");
    for (std::size_t i = 0; i + 1 < o.path.centerline_m.size(); ++i) {
      const Vec3 a = o.path.centerline_m[i], b = o.path.centerline_m[i + 1];
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      Box box;
      box.center_m = {(a.x + b.x) / 2, (a.y + b.y) / 2, (bottom + top) / 2};
      box.half_extents_m = {length / 2 + width / 2, width / 2, (top - bottom) / 2};
      box.rotation = rotation_rpy(0, 0, std::atan2(b.y - a.y, b.x - a.x));
      box.faces = 0x1f;  // standing on its base: never pushes downwards
      model.boxes.push_back(box);
    }
  }

  // a file an object names, relative to the scene file
  std::string beside_scene(const Map& m) const {
    const std::filesystem::path name = m.text("file");
    const std::string path = name.is_absolute() ? name.string() : (std::filesystem::path(file).parent_path() / name).string();
    if (!std::filesystem::is_regular_file(path)) m.fail("file", "there is no file " + path, "give the file's path relative to the scene file");
    return path;
  }

  // a closed triangle mesh from a file, scaled, rotated and placed
  void mesh(const Map& m, Object& o) {
    const auto rpy = m.vec3("rpy_deg", {0, 0, 0});
    const Mat3 rotation = rotation_rpy(rpy[0] * kDegree, rpy[1] * kDegree, rpy[2] * kDegree);
    o.mesh = static_cast<int>(model.meshes.size());
    model.meshes.push_back(load_mesh(beside_scene(m), m.positive("scale", 1.0), rotation, vec(m.vec3("center_m", {0, 0, 0}))));
  }

  // a height map: a closed solid over a grid of heights from a CSV file or a 16-bit PNG (its
  // pixel values up to max_height_m), down to bottom_z_m
  void heightmap(const Map& m, Object& o) {
    const std::string source = beside_scene(m);
    const bool png = source.size() > 4 && source.compare(source.size() - 4, 4, ".png") == 0;
    if (png && !m.has("max_height_m")) m.fail("file", "a PNG height map needs max_height_m", "add max_height_m: the height (m) of the pixel value 65535");
    if (!png && m.has("max_height_m")) m.fail("max_height_m", "max_height_m is for PNG height maps", "remove it: a CSV gives its heights in metres");
    const HeightGrid grid = png ? read_png_heights(source, m.positive("max_height_m")) : read_heights(source);
    const Vec3 centre = vec(m.vec3("center_m", {0, 0, 0}));
    const double bottom = m.number("bottom_z_m", centre.z);
    for (double h : grid.heights_m) {
      if (centre.z + h <= bottom) m.fail("bottom_z_m", "a height of " + source + " is at or below bottom_z_m", "put bottom_z_m below the lowest height (center_m z + height)");
    }
    o.mesh = static_cast<int>(model.meshes.size());
    model.meshes.push_back(heightfield_mesh(grid.heights_m, grid.rows, grid.cols, m.positive("cell_m"), centre, bottom));
  }

  // a capsule from_m -> to_m (a sphere: one centre), its surface radius_m from the axis
  void capsule(const Map& m, Object& o, bool sphere) {
    o.axis_from_m = vec(m.vec3(sphere ? "center_m" : "from_m"));
    o.axis_to_m = sphere ? o.axis_from_m : vec(m.vec3("to_m"));
    o.radius_m = m.positive("radius_m");
    const Vec3 axis = o.axis_to_m - o.axis_from_m;
    if (!sphere && norm(axis) <= 0.0) m.fail("to_m", "the capsule's ends are the same point", "give two different ends, or use type: sphere");
    // on the axis itself: up for a sphere, else the horizontal (or x) direction across the axis
    const Vec3 across = std::abs(axis.z) < 0.9 * norm(axis) ? Vec3{-axis.y, axis.x, 0.0} : Vec3{axis.z, 0.0, -axis.x};
    o.axis_normal = sphere ? Vec3{0, 0, 1} : across * (1.0 / norm(across));
  }

  void objects(const Map& scene) {
    for (const auto& n : scene.list("objects")) {
      Map m(n, file, "object", {"name", "type", "point_m", "normal", "center_m", "half_extents_m", "rpy_deg", "boxes",
                                "points_m", "width_m", "bottom_z_m", "top_z_m", "file", "scale", "cell_m", "max_height_m", "radius_m", "from_m", "to_m"});
      Object o;
      o.name = m.text("name");
      check_new_name(m, o.name);
      o.line = m.line();
      o.first_box = static_cast<int>(model.boxes.size());
      const std::string type = m.text("type");
      if (type == "plane") {
        o.type = ObjectType::plane;
        o.plane_point_m = vec(m.vec3("point_m", {0, 0, 0}));
        const Vec3 normal = vec(m.vec3("normal"));
        if (norm(normal) < 1e-12) m.fail("normal", "the plane normal is zero", "give the outward normal, e.g. [0, 0, 1]");
        o.plane_normal = normal * (1.0 / norm(normal));
      } else if (type == "box") {
        o.type = ObjectType::boxes;
        model.boxes.push_back(box(m));
      } else if (type == "union") {
        o.type = ObjectType::boxes;
        for (const auto& b : m.list("boxes")) model.boxes.push_back(box(Map(b, file, "union box", {"center_m", "half_extents_m", "rpy_deg"})));
        if (model.boxes.size() == static_cast<std::size_t>(o.first_box)) m.fail("boxes", "a union needs at least one box", "list its boxes under boxes:");
      } else if (type == "path") {
        o.type = ObjectType::boxes;
        path(m, o);
      } else if (type == "mesh" || type == "heightmap") {
        o.type = ObjectType::mesh;
        type == "mesh" ? mesh(m, o) : heightmap(m, o);
      } else if (type == "sphere" || type == "capsule") {
        o.type = ObjectType::capsule;
        capsule(m, o, type == "sphere");
      } else {
        m.fail("type", "unknown object type '" + type + "'", "use plane, box, union, path, mesh, heightmap, sphere or capsule");
      }
      o.shape = type;
      o.box_count = static_cast<int>(model.boxes.size()) - o.first_box;
      model.objects.push_back(o);
    }
  }

  // the masses a contact entry names: body (centre and grid), grid, centre, or a list of names
  std::vector<int> contact_points(const Map& m) {
    const YAML::Node n = m.get("masses");
    std::vector<int> out;
    if (n.IsScalar() && (n.Scalar() == "body" || n.Scalar() == "grid" || n.Scalar() == "center")) {
      if (model.proxies.empty()) m.fail("masses", "masses: " + n.Scalar() + " needs a body: section", "add a body, or list mass names");
      for (const Proxy& p : model.proxies) {
        if (n.Scalar() != "grid") out.push_back(p.point);
        for (int i = 0; n.Scalar() != "center" && i < p.rows * p.cols; ++i) out.push_back(p.first_body + i);
      }
      return out;
    }
    if (!n.IsSequence()) m.fail("masses", "masses must be body, grid, center or a list of names", "write e.g. masses: [m1, m2]");
    for (const auto& item : n) {
      const std::string name = config::scalar(file, item, "a mass in contacts");
      const int i = model.find_point(name);
      if (i < 0) config::fail(file, item, "unknown mass '" + name + "' in contacts", "name a mass, or body/grid/center");
      if (model.points[i].kind == PointKind::fixed) config::fail(file, item, "fixed point '" + name + "' cannot touch an object", "name a mass or a body mass");
      out.push_back(i);
    }
    return out;
  }

  // friction: {static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}; absent: none
  Friction friction(const Map& contact) {
    if (!contact.has("friction")) return {};
    Map m(contact.get("friction"), file, "contact.friction", {"static", "dynamic", "stiffness_n_per_m"});
    const char* example = "write e.g. friction: {static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}";
    for (const char* key : {"static", "dynamic", "stiffness_n_per_m"}) {
      if (!m.has(key)) m.fail(key, std::string("contact.friction needs ") + key, example);
    }
    Friction f;
    f.static_coeff = m.positive("static", 0.0, true);
    f.dynamic_coeff = m.positive("dynamic", 0.0, true);
    f.stiffness_n_per_m = m.positive("stiffness_n_per_m");
    if (f.dynamic_coeff > f.static_coeff) {
      m.fail("dynamic", "contact.friction.dynamic (" + m.get("dynamic").Scalar() + ") is above static (" + m.get("static").Scalar() + ")",
             "make dynamic <= static: a contact never slides against more friction than it sticks with");
    }
    return f;
  }

  void contacts(const Map& scene) {
    for (const auto& n : scene.list("contacts")) {
      Map m(n, file, "contact", {"masses", "objects", "stiffness_n_per_m", "damping_n_s_per_m", "edge_skin_m", "passive", "friction"});
      const std::vector<int> pts = contact_points(m);
      const YAML::Node objs = m.get("objects");
      if (!objs.IsSequence()) m.fail("objects", "objects must be a list of object names", "write e.g. objects: [bridge, floor]");
      const double k = m.positive("stiffness_n_per_m");
      const double z = m.positive("damping_n_s_per_m", 0.0, true);
      const double skin = m.positive("edge_skin_m", 0.001, true);
      const bool passive = m.flag("passive", false);
      const Friction fr = friction(m);
      for (const auto& o : objs) {
        const std::string name = config::scalar(file, o, "an object in contacts");
        const int oi = model.find_object(name);
        if (oi < 0) config::fail(file, o, "unknown object '" + name + "'", "name an object defined under objects:");
        for (int p : pts) model.contacts.push_back({p, oi, k, z, skin, m.line(), passive, fr});
      }
    }
  }

  void settings(const Map& scene) {
    model.name = scene.text("scene", file);
    model.source = file;
    const double rate = scene.positive("rate_hz", 5000.0);
    if (rate < 1.0 || rate > 1.0e6) scene.fail("rate_hz", "rate_hz must be from 1 to 1000000", "the loop runs from 1 to 44 kHz; 5000 is the default");
    model.set_rate(rate);
    const std::string integrator = scene.text("integrator", "cordis");
    if (integrator == "cordis") model.integrator = Integrator::cordis;
    else if (integrator == "symplectic_euler") model.integrator = Integrator::symplectic_euler;
    else if (integrator == "implicit_euler") model.integrator = Integrator::implicit_euler;
    else scene.fail("integrator", "unknown integrator '" + integrator + "'", "use cordis, symplectic_euler or implicit_euler");
    model.gravity_m_per_s2 = vec(scene.vec3("gravity_m_per_s2", {0, 0, 0}));
    model.device_profile = scene.text("device_profile", "");
    if (scene.has("limits")) {
      Map l(scene.get("limits"), file, "limits", {"max_position_m", "max_speed_m_per_s"});
      model.limits.max_position_m = l.positive("max_position_m", model.limits.max_position_m);
      model.limits.max_speed_m_per_s = l.positive("max_speed_m_per_s", model.limits.max_speed_m_per_s);
    }
  }

  // the task's surface and the line along it: a path object's own centreline, or for any
  // other object (a height map, a mesh, a capsule...) points_m, top_z_m and width_m here
  void task(const Map& scene) {
    if (!scene.has("task")) return;
    Map t(scene.get("task"), file, "task", {"surface", "points_m", "top_z_m", "width_m"});
    model.task_surface = t.text("surface");
    const int o = model.find_object(model.task_surface);
    if (o < 0) t.fail("surface", "no object '" + model.task_surface + "' for the task" + config::did_you_mean(model.task_surface, object_names()), "name one of the scene's objects");
    const Object& surface = model.objects[o];
    if (surface.is_path) {
      for (const char* key : {"points_m", "top_z_m", "width_m"}) {
        if (t.has(key)) t.fail(key, std::string("the path object '") + surface.name + "' gives the task its own centreline, width and top", std::string("remove ") + key);
      }
      model.task_path = surface.path;
      return;
    }
    if (surface.type == ObjectType::plane) t.fail("surface", "a plane cannot be the task's surface (nothing to fall off)", "name a path, mesh, height map, sphere or capsule");
    for (const char* key : {"points_m", "top_z_m", "width_m"}) {
      if (!t.has(key)) t.fail("surface", std::string("the task on '") + surface.name + "' (not a path object) needs " + key,
                              "give the line to follow (points_m: [[x, y], ...]), the height of the top along it (top_z_m) and the width of the top (width_m), in m");
    }
    model.task_path.width_m = t.positive("width_m");
    model.task_path.top_z_m = t.number("top_z_m");
    model.task_path.centerline_m = centreline(t, model.task_path.top_z_m, "a task line");
  }

  std::vector<std::string> object_names() const {
    std::vector<std::string> names;
    for (const Object& o : model.objects) names.push_back(o.name);
    return names;
  }
};

}  // namespace

std::string grid_point_name(const std::string& body, int row, int col) {
  return body + "/r" + std::to_string(row) + "c" + std::to_string(col);
}

std::vector<std::string> files_beside_scene(const std::string& path) {
  std::vector<std::string> files;
  try {
    const YAML::Node objects = YAML::LoadFile(path)["objects"];
    if (!objects.IsSequence()) return files;
    for (const auto& o : objects) {
      if (!o.IsMap() || !o["file"] || !o["file"].IsScalar()) continue;
      const std::filesystem::path file = std::filesystem::path(o["file"].Scalar()).lexically_normal();
      if (file.is_relative() && !file.empty() && *file.begin() != "..") files.push_back(file.string());
    }
  } catch (const std::exception&) {
    files.clear();
  }
  return files;
}

Model load_scene(const std::string& given) {
  const std::string path = config::find_file(given);
  const YAML::Node root = config::load_file(path);
  Loader loader{path, {}};
  const Map scene(root, path, "scene",
                  {"scene", "description", "rate_hz", "integrator", "gravity_m_per_s2", "device_profile", "limits", "masses",
                   "fixed", "body", "links", "objects", "contacts", "task"});
  loader.settings(scene);
  loader.masses(scene);
  loader.body(scene);
  loader.links(scene);
  loader.objects(scene);
  loader.contacts(scene);
  loader.task(scene);
  loader.model.index_boxes();
  if (loader.model.points.empty()) scene.fail("masses", "the scene has no masses and no body", "add masses: or body:");
  return loader.model;
}

}  // namespace enact::physics
