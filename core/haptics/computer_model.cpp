#include "core/haptics/computer_model.h"

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/config/suggest.h"
#include "core/config/yaml.h"

namespace enact::haptics {
namespace {

std::uint32_t all(int masses) { return masses >= 32 ? 0xffffffffu : (1u << masses) - 1u; }

// a list of grid mass indices (row-major) as a bitmask
std::uint32_t parse_indices(const config::Map& m, const char* key, int masses) {
  const YAML::Node n = m.get(key);
  if (!n.IsSequence()) m.fail(key, std::string(key) + " must be a list of grid mass indices", "write e.g. " + std::string(key) + ": [0, 1, 2, 3] (row-major)");
  std::uint32_t mask = 0;
  for (const auto& item : n) {
    int i = -1;
    if (!item.IsScalar() || !YAML::convert<int>::decode(item, i) || i < 0 || i >= masses) {
      config::fail(m.file(), item, std::string(key) + " index must be from 0 to " + std::to_string(masses - 1), "list grid mass indices, row-major");
    }
    mask |= 1u << i;
  }
  return mask;
}

// "grid", "center", "all", "none" or a list of grid indices
void parse_force(const config::Map& m, int masses, ComputerModel& cm) {
  const YAML::Node n = m.get("force");
  if (!n.IsScalar()) {
    cm.force_grid_mask = parse_indices(m, "force", masses);
    return;
  }
  const std::string s = n.Scalar();
  if (s != "grid" && s != "center" && s != "all" && s != "none") m.fail("force", "unknown force source '" + s + "'", "use grid, center, all, none or a list of grid mass indices");
  cm.force_grid_mask = (s == "grid" || s == "all") ? all(masses) : 0;
  cm.force_center = s == "center" || s == "all";
}

}  // namespace

std::vector<std::string> preset_names() { return {"CM0", "CM1", "CM2", "CM3", "P", "T", "PT"}; }

std::optional<ComputerModel> preset(const std::string& name, int masses) {
  const std::uint32_t grid = all(masses);
  ComputerModel cm;
  cm.name = name;
  if (name == "CM0") cm = {name, grid, false, 0, PinDrive::none, 0.0};
  else if (name == "CM1") cm = {name, grid, false, grid, PinDrive::contact, 0.0};
  // about 0.3 cm of extra displacement after first contact before force is felt
  else if (name == "CM2") cm = {name, grid, false, grid, PinDrive::contact, 0.003};
  else if (name == "CM3") cm = {name, grid, false, grid, PinDrive::inverted, 0.0};
  else if (name == "P") cm = {name, 0, true, 0, PinDrive::none, 0.0};
  else if (name == "T") cm = {name, 0, false, grid, PinDrive::contact, 0.0};
  else if (name == "PT") cm = {name, 0, true, grid, PinDrive::contact, 0.0};
  else return std::nullopt;
  return cm;
}

ComputerModel resolve_computer_model(const std::string& name_or_path, int masses) {
  if (auto cm = preset(name_or_path, masses)) return *cm;
  const bool looks_like_file = name_or_path.find('/') != std::string::npos || name_or_path.ends_with(".yaml") || name_or_path.ends_with(".yml");
  if (!looks_like_file) {
    std::string names;
    for (const auto& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
    throw config::Error("unknown preset " + name_or_path + config::did_you_mean(name_or_path, preset_names()) + "\n  fix: use a preset (" + names +
                        ") or a YAML file defining a computer model");
  }
  const std::string path = config::find_file(name_or_path);
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "computer model", {"name", "description", "force", "pins", "pin_masses", "threshold_m"});
  ComputerModel cm;
  cm.name = m.text("name");
  parse_force(m, masses, cm);
  const std::string pins = m.text("pins", "none");
  if (pins == "none") cm.pins = PinDrive::none;
  else if (pins == "contact") cm.pins = PinDrive::contact;
  else if (pins == "inverted") cm.pins = PinDrive::inverted;
  else m.fail("pins", "unknown pin drive '" + pins + "'", "use none, contact or inverted");
  cm.pin_mask = cm.pins == PinDrive::none ? 0 : all(masses);
  if (m.has("pin_masses")) cm.pin_mask = parse_indices(m, "pin_masses", masses);
  cm.threshold_m = m.positive("threshold_m", 0.0, true);
  if (cm.threshold_m > kMaxThreshold_m) {
    m.fail("threshold_m", "threshold_m " + config::number(cm.threshold_m) + " m is deeper than any device reaches into an object",
           "give at most " + config::number(kMaxThreshold_m) + " m (CM2's is 0.003)");
  }
  return cm;
}

void apply(const ComputerModel& cm, physics::Model& model, int proxy) {
  const physics::Proxy& p = model.proxies.at(proxy);
  model.points[p.point].feeds_device = cm.force_center;
  model.points[p.point].contact_threshold_m = cm.threshold_m;
  for (int i = 0; i < p.rows * p.cols; ++i) {
    physics::Point& pt = model.points[p.first_body + i];
    pt.feeds_device = (cm.force_grid_mask >> i) & 1u;
    pt.contact_threshold_m = cm.threshold_m;
  }
}

std::uint32_t pins(const ComputerModel& cm, const physics::Model& model, const physics::State& state, int proxy) {
  if (cm.pins == PinDrive::none) return 0;
  const physics::Proxy& p = model.proxies[proxy];
  std::uint32_t out = 0;
  for (int i = 0; i < p.rows * p.cols; ++i) {
    const bool touching = state.in_contact[p.first_body + i] != 0;
    const bool up = cm.pins == PinDrive::contact ? touching : !touching;
    if (up && ((cm.pin_mask >> i) & 1u)) out |= 1u << i;
  }
  return out;
}

}  // namespace enact::haptics
