#include "core/devices/virtual_subject.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <utility>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/config/yaml.h"

namespace enact::devices {
namespace {

using math::Vec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// how fast the felt height of the top follows the hand while on it
constexpr double kTopTime_s = 0.5;
// touching, but this far below the top: on the floor, not on the bridge
constexpr double kFloorBelowTop_m = 0.006;
// no wall felt for this long while climbing: past its top (or slipped off it)
constexpr double kWallGone_s = 0.05;
// the pins' rise time and more: how long after a reset the pins in the air are known
constexpr double kPinsSettle_s = 0.05;
// the arm stiffness a subject assumes when the device has no hand spring (the device default)
constexpr double kFreeHandStiffness_n_per_m = 300.0;
// how far above the remembered top a subject climbs a wall and crosses over
constexpr double kAboveTop_m = 0.001;
// how fast the subject stops pressing when it has fallen, and the experimenter's hand speed
constexpr double kHoldTime_s = 0.1;
constexpr double kRepositionSpeed_m_per_s = 0.05;
// the slowest a subject moves over a top it feels slipping away (fraction of its speed)
constexpr double kCarefulSlowdown = 0.5;

// one number of the subject file: its key, where it lives, its allowed range
struct Field {
  const char* key;
  double SubjectParams::*member;
  double min;
  double max;
};

constexpr double kTiny = 1e-9;  // "greater than zero"

const Field kFields[] = {
    {"speed_m_per_s", &SubjectParams::speed_m_per_s, kTiny, 1.8},
    {"press_n", &SubjectParams::press_n, 0.0, 20.0},
    {"descend_m_per_s", &SubjectParams::descend_m_per_s, kTiny, 1.0},
    {"search_m_per_s", &SubjectParams::search_m_per_s, kTiny, 1.0},
    {"climb_m_per_s", &SubjectParams::climb_m_per_s, kTiny, 1.0},
    {"push_n", &SubjectParams::push_n, 0.0, 20.0},
    {"search_m", &SubjectParams::search_m, kTiny, 0.06},
    {"over_m", &SubjectParams::over_m, 0.0, 0.06},
    {"settle_s", &SubjectParams::settle_s, 0.0, 10.0},
    {"reposition_after_s", &SubjectParams::reposition_after_s, kTiny, 600.0},
    {"touch_n", &SubjectParams::touch_n, kTiny, 10.0},
    {"drop_m", &SubjectParams::drop_m, kTiny, 0.02},
    {"reaction_delay_s", &SubjectParams::reaction_delay_s, 0.0, 1.0},
    {"control_period_s", &SubjectParams::control_period_s, 1e-4, 0.05},
    {"pin_pitch_m", &SubjectParams::pin_pitch_m, kTiny, 0.01},
    {"tactile_use", &SubjectParams::tactile_use, 0.0, 1.0},
    {"tactile_gain_per_s", &SubjectParams::tactile_gain_per_s, 0.0, 50.0},
    {"tactile_turn_per_s_m", &SubjectParams::tactile_turn_per_s_m, 0.0, 5000.0},
    {"inverted_pin_use", &SubjectParams::inverted_pin_use, 0.0, 1.0},
    {"motor_noise", &SubjectParams::motor_noise, 0.0, 5.0},
    {"motor_noise_floor_m_per_s", &SubjectParams::motor_noise_floor_m_per_s, 0.0, 0.1},
    {"noise_time_s", &SubjectParams::noise_time_s, kTiny, 10.0},
    {"route_memory", &SubjectParams::route_memory, 0.0, 1.0},
    {"heading_error_deg", &SubjectParams::heading_error_deg, 0.0, 90.0},
    {"length_error", &SubjectParams::length_error, 0.0, 1.0},
    {"between_subjects", &SubjectParams::between_subjects, 0.0, 1.0},
};

// "" when the value is in the field's range, else the problem
std::string out_of_range(const Field& f, double value) {
  if (std::isfinite(value) && value >= f.min && value <= f.max) return "";
  const std::string low = f.min == kTiny ? "above 0" : "from " + config::number(f.min);
  return std::string(f.key) + " is " + config::number(value) + ": it must be " + low + " to " + config::number(f.max);
}

// "" when the route is usable, else the problem
std::string bad_route(const SubjectParams& p) {
  if (p.route_headings_deg.empty()) return "route.headings_deg is empty";
  if (p.route_headings_deg.size() != p.route_lengths_m.size()) return "route.headings_deg and route.lengths_m differ in length";
  for (double h : p.route_headings_deg) {
    if (!std::isfinite(h)) return "route.headings_deg holds a value that is not finite";
  }
  for (double l : p.route_lengths_m) {
    if (!(l > 0.0 && l < 1.0)) return "route.lengths_m holds " + config::number(l) + ": each length must be above 0 and below 1 m";
  }
  return "";
}

constexpr const char* kRouteFix = "give route: {headings_deg: [45, -45, 45], lengths_m: [0.021, 0.021, 0.021]}: one heading and one length per segment";

// a subject's trait factor: log-normal around 1 with sd `spread`, kept within [0.5, 2]
double trait(math::Random& r, double spread) { return std::clamp(std::exp(spread * r.normal()), 0.5, 2.0); }

}  // namespace

SubjectParams load_subject(const std::string& given) {
  const std::string path = config::find_file(given);
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "subject",
                      {"name", "route", "speed_m_per_s", "press_n", "descend_m_per_s", "search_m_per_s", "climb_m_per_s", "push_n",
                       "search_m", "over_m", "settle_s", "reposition_after_s", "touch_n", "drop_m", "reaction_delay_s",
                       "control_period_s", "pin_pitch_m", "tactile_use", "tactile_gain_per_s", "tactile_turn_per_s_m", "inverted_pin_use", "motor_noise",
                       "motor_noise_floor_m_per_s", "noise_time_s", "route_memory", "heading_error_deg", "length_error",
                       "between_subjects"});
  SubjectParams p;
  p.name = std::filesystem::path(path).stem().string();
  p.name = m.text("name", p.name);
  for (const Field& f : kFields) {
    if (!m.has(f.key)) continue;
    const double value = m.number(f.key);
    if (const std::string problem = out_of_range(f, value); !problem.empty()) m.fail(f.key, problem, "set a value in that range");
    p.*f.member = value;
  }
  if (m.has("route")) {
    const config::Map route(m.get("route"), path, "route", {"headings_deg", "lengths_m"});
    const YAML::Node headings = route.get("headings_deg"), lengths = route.get("lengths_m");
    if (!headings.IsSequence() || !lengths.IsSequence()) route.fail("headings_deg", "route.headings_deg and route.lengths_m must be lists", kRouteFix);
    p.route_headings_deg = config::numbers(path, headings, headings.size(), "route.headings_deg");
    p.route_lengths_m = config::numbers(path, lengths, lengths.size(), "route.lengths_m");
    if (const std::string problem = bad_route(p); !problem.empty()) route.fail("lengths_m", problem, kRouteFix);
  }
  return p;
}

void validate(const SubjectParams& p, const std::string& source) {
  for (const Field& f : kFields) {
    if (const std::string problem = out_of_range(f, p.*f.member); !problem.empty()) {
      throw config::Error(source + ": " + problem + "\n  fix: set a value in that range");
    }
  }
  if (const std::string problem = bad_route(p); !problem.empty()) throw config::Error(source + ": " + problem + "\n  fix: " + kRouteFix);
}

VirtualSubject::VirtualSubject(SubjectParams params, std::uint64_t subject_seed, std::uint64_t noise_seed)
    : params_(std::move(params)), noise_seed_(noise_seed) {
  validate(params_, "subject '" + params_.name + "'");
  // this subject's traits
  math::Random traits(subject_seed);
  speed_m_per_s_ = params_.speed_m_per_s * trait(traits, params_.between_subjects);
  delay_s_ = std::min(1.0, params_.reaction_delay_s * trait(traits, params_.between_subjects));
  noise_factor_ = trait(traits, params_.between_subjects);
  // the control clock and the memory of the last reaction delay
  period_ns_ = std::max<std::int64_t>(1, std::llround(params_.control_period_s * 1e9));
  period_s_ = static_cast<double>(period_ns_) * 1e-9;
  delay_ticks_ = static_cast<int>(std::lround(delay_s_ / period_s_));
  percepts_.assign(static_cast<std::size_t>(delay_ticks_) + 1, Percept{});
  const std::size_t segments = params_.route_headings_deg.size();
  heading_x_.assign(segments, 0.0);
  heading_y_.assign(segments, 0.0);
  length_m_.assign(segments, 0.0);
  reset(HandStart{});
}

void VirtualSubject::reset(const HandStart& start) noexcept {
  noise_ = math::Random(noise_seed_);
  start_m_ = start.start_m;
  stiffness_n_per_m_ = start.hand_stiffness_n_per_m > 0.0 ? start.hand_stiffness_n_per_m : kFreeHandStiffness_n_per_m;
  // the route as remembered this trial
  const double fuzz = 1.0 - params_.route_memory;
  for (std::size_t i = 0; i < length_m_.size(); ++i) {
    const double heading = (params_.route_headings_deg[i] + fuzz * params_.heading_error_deg * noise_.normal()) * kDeg;
    heading_x_[i] = std::sin(heading);
    heading_y_[i] = std::cos(heading);
    length_m_[i] = params_.route_lengths_m[i] * std::max(0.2, 1.0 + fuzz * params_.length_error * noise_.normal());
  }
  // at rest at the start, felt so for the whole reaction delay
  std::fill(percepts_.begin(), percepts_.end(), Percept{start_m_, {}, 0});
  head_ = 0;
  pins_up_now_ = 0;
  air_pins_ = 0;
  air_known_ = false;
  tactile_use_ = params_.tactile_use;
  segment_ = 0;
  segment_travel_m_ = turn_rad_ = 0.0;
  next_control_ns_ = from_ns_ = 0;
  target_from_ = target_to_ = start_m_;
  noise_m_per_s_ = {};
  phase_ = Phase::settle;
  phase_ns_ = now_ns_ = 0;
  lost_ = false;
  lost_at_ns_ = wall_ns_ = 0;
  support_z_m_ = top_z_m_ = start_m_.z;
  top_known_ = false;
  last_top_x_m_ = start_m_.x;
  last_top_y_m_ = start_m_.y;
  side_cue_ = 0.0;
  dir_x_ = dir_y_ = 0.0;
  phase_travel_m_ = 0.0;
  search_leg_ = 0;
  losses_ = repositions_ = 0;
}

void VirtualSubject::feel_pins(const float* levels, int rows, int cols) noexcept {
  const int count = std::min(rows * cols, 32);
  std::uint32_t up = 0;
  for (int i = 0; i < count; ++i) up |= levels[i] > 0.5f ? 1u << i : 0u;
  pins_up_now_ = up;
  pin_rows_ = rows;
  pin_cols_ = cols;
}

Vec3 VirtualSubject::target(std::int64_t time_ns, const HandFeel& feel) noexcept {
  // one intention per control period, from what was felt a reaction delay ago
  while (time_ns >= next_control_ns_) {
    now_ns_ = next_control_ns_;
    control({feel.handle_m, feel.force_on_hand_n, pins_up_now_});
    next_control_ns_ += period_ns_;
  }
  // the hand moves smoothly from one intention to the next
  const double a = std::clamp(static_cast<double>(time_ns - from_ns_) / static_cast<double>(period_ns_), 0.0, 1.0);
  return target_from_ + (target_to_ - target_from_) * a;
}

VirtualSubject::Contact VirtualSubject::contact(const Percept& p) const noexcept {
  Contact c;
  c.force_up = p.force_n.z > params_.touch_n;
  if (!air_known_ || tactile_use_ <= 0.0 || pin_cols_ <= 0) return c;
  // pins that differ from what they showed in the air, and where they are under the fingertip
  const std::uint32_t differ = p.pins_up ^ air_pins_;
  for (int i = 0; i < pin_rows_ * pin_cols_; ++i) {
    if (((differ >> i) & 1u) == 0) continue;
    const int row = i / pin_cols_, col = i % pin_cols_;
    c.cx_m += (col - 0.5 * (pin_cols_ - 1)) * params_.pin_pitch_m;
    c.cy_m += (0.5 * (pin_rows_ - 1) - row) * params_.pin_pitch_m;
    ++c.pins;
  }
  if (c.pins > 0) {
    c.cx_m /= c.pins;
    c.cy_m /= c.pins;
  }
  return c;
}

double VirtualSubject::heading_x() const noexcept {
  return heading_x_[segment_] * std::cos(turn_rad_) + heading_y_[segment_] * std::sin(turn_rad_);
}

double VirtualSubject::heading_y() const noexcept {
  return heading_y_[segment_] * std::cos(turn_rad_) - heading_x_[segment_] * std::sin(turn_rad_);
}

void VirtualSubject::enter(Phase phase) noexcept {
  repositions_ += phase == Phase::reposition;
  phase_ = phase;
  phase_ns_ = now_ns_;
  phase_travel_m_ = 0.0;
}

void VirtualSubject::move(double vx, double vy, double vz) noexcept {
  // signal-dependent motor noise, low-pass filtered (an Ornstein-Uhlenbeck process whose
  // stationary sd is sigma)
  const double sigma = noise_factor_ * (params_.motor_noise * std::hypot(vx, vy) + params_.motor_noise_floor_m_per_s);
  const double a = std::min(1.0, period_s_ / params_.noise_time_s);
  const double kick = sigma * std::sqrt(2.0 * a);
  noise_m_per_s_.x = noise_m_per_s_.x * (1.0 - a) + kick * noise_.normal();
  noise_m_per_s_.y = noise_m_per_s_.y * (1.0 - a) + kick * noise_.normal();
  target_from_ = target_to_;
  target_to_ = target_from_ + (Vec3{vx, vy, vz} + Vec3{noise_m_per_s_.x, noise_m_per_s_.y, 0.0}) * period_s_;
  from_ns_ = now_ns_;
}

void VirtualSubject::on_top(const Percept& p, const Contact& c) noexcept {
  lost_ = false;
  support_z_m_ = p.handle_m.z;
  last_top_x_m_ = p.handle_m.x;
  last_top_y_m_ = p.handle_m.y;
  top_z_m_ += (p.handle_m.z - top_z_m_) * std::min(1.0, period_s_ / kTopTime_s);
  // where the pins say the bridge is, across the heading (+: to the right)
  const int pins = pin_rows_ * pin_cols_;
  if (c.pins > 0 && c.pins < pins) side_cue_ = c.cx_m * heading_y() - c.cy_m * heading_x();
  if (c.pins == pins) side_cue_ = 0.0;
}

void VirtualSubject::start_search(const Percept& p) noexcept {
  ++losses_;
  lost_ = true;
  lost_at_ns_ = now_ns_;
  search_leg_ = 0;
  // which side the bridge is on: the pins' last hint, else away from the drift off the top,
  // else a guess
  const double nx = heading_y(), ny = -heading_x();  // right of the heading
  const double drift = (p.handle_m.x - last_top_x_m_) * nx + (p.handle_m.y - last_top_y_m_) * ny;
  double side = noise_.uniform() < 0.5 ? -1.0 : 1.0;
  if (tactile_use_ > 0.0 && std::abs(side_cue_) > 0.25 * params_.pin_pitch_m) side = side_cue_ > 0.0 ? 1.0 : -1.0;
  else if (std::abs(drift) > 0.0003) side = drift > 0.0 ? -1.0 : 1.0;
  dir_x_ = side * nx;
  dir_y_ = side * ny;
  support_z_m_ = p.handle_m.z;  // stop pressing: hold the height reached
  enter(Phase::search);
}

void VirtualSubject::control(const Percept& now) noexcept {
  // remember now, act on what was felt a reaction delay ago
  head_ = (head_ + 1) % percepts_.size();
  percepts_[head_] = now;
  const Percept& p = percepts_[(head_ + 1) % percepts_.size()];
  const Contact c = contact(p);
  // landed on the top while looking for it
  const bool back_on_top = top_known_ && c.touching() && p.handle_m.z >= top_z_m_ - 2.0 * params_.drop_m;

  // lost too long, whatever it is doing: the experimenter takes over
  if (lost_ && phase_ != Phase::reposition && static_cast<double>(now_ns_ - lost_at_ns_) * 1e-9 > params_.reposition_after_s) {
    return enter(Phase::reposition);
  }
  switch (phase_) {
    case Phase::settle: return settle(p);
    case Phase::descend: return descend(p, c);
    case Phase::follow: return follow(p, c);
    case Phase::search: return search(p, c, back_on_top);
    case Phase::climb: return climb(p, c, back_on_top);
    case Phase::over: return over(p, c, back_on_top);
    case Phase::reposition: return reposition();
  }
}

void VirtualSubject::settle(const Percept& p) noexcept {
  // long enough to have felt the pins in the air (they rise within tens of ms)
  move(0.0, 0.0, 0.0);
  const double since_s = static_cast<double>(now_ns_ - phase_ns_) * 1e-9;
  if (since_s < std::max(params_.settle_s, delay_s_ + kPinsSettle_s)) return;
  // what the pins show in the air; raised there, they rise off contact (inverted)
  air_pins_ = p.pins_up;
  air_known_ = true;
  tactile_use_ = params_.tactile_use * (2 * std::popcount(air_pins_) > pin_rows_ * pin_cols_ ? params_.inverted_pin_use : 1.0);
  enter(Phase::descend);
}

void VirtualSubject::descend(const Percept& p, const Contact& c) noexcept {
  if (c.touching()) {
    if (!top_known_) top_z_m_ = p.handle_m.z;
    top_known_ = true;
    on_top(p, c);
    move(0.0, 0.0, 0.0);
    enter(Phase::follow);
    return;
  }
  if (top_known_ && p.handle_m.z < top_z_m_ - 2.0 * params_.drop_m) return start_search(p);  // missed the top
  move(0.0, 0.0, -params_.descend_m_per_s);
}

void VirtualSubject::follow(const Percept& p, const Contact& c) noexcept {
  if (c.touching()) on_top(p, c);
  const bool dropped = !c.touching() && p.handle_m.z < support_z_m_ - params_.drop_m;
  const bool on_floor = c.touching() && p.handle_m.z < top_z_m_ - kFloorBelowTop_m;
  if (dropped || on_floor) return start_search(p);
  // along the remembered heading, slower when the pins say the top is slipping away;
  // where the pins in contact lie across the heading, the subject steers and turns
  const double hx = heading_x(), hy = heading_y();
  const double across = c.cx_m * hy - c.cy_m * hx;  // + right of the heading
  const int pins = pin_rows_ * pin_cols_;
  const double careful = c.pins > 0 ? 1.0 - kCarefulSlowdown * tactile_use_ * (1.0 - static_cast<double>(c.pins) / pins) : 1.0;
  const double speed = speed_m_per_s_ * careful;
  const double steer = tactile_use_ * params_.tactile_gain_per_s * across;
  turn_rad_ += tactile_use_ * params_.tactile_turn_per_s_m * across * period_s_;
  move(speed * hx + steer * hy, speed * hy - steer * hx, 0.0);
  // press down: the hand a press's worth below where it is; when the pins show contact
  // that the force does not (a force felt only past a threshold, CM2), hold the height
  const double press_n = !c.force_up && c.pins > 0 ? 0.0 : params_.press_n;
  target_to_.z = p.handle_m.z - press_n / stiffness_n_per_m_;
  // something ahead holds the hand back: rise over it instead of pressing
  if (-(p.force_n.x * hx + p.force_n.y * hy) > params_.push_n) target_to_.z = std::max(target_from_.z, p.handle_m.z) + params_.climb_m_per_s * period_s_;
  // the route, by efference copy
  segment_travel_m_ += speed * period_s_;
  if (segment_ + 1 < length_m_.size() && segment_travel_m_ >= length_m_[segment_]) {
    ++segment_;
    segment_travel_m_ = 0.0;
    turn_rad_ = 0.0;
  }
}

// back on the top (a surface pushing up, when `need_force`): follow it again; true if so
bool VirtualSubject::landed(const Percept& p, const Contact& c, bool back_on_top, bool need_force) noexcept {
  if (!back_on_top || (need_force && !c.force_up)) return false;
  on_top(p, c);
  move(0.0, 0.0, 0.0);
  enter(Phase::follow);
  return true;
}

void VirtualSubject::search(const Percept& p, const Contact& c, bool back_on_top) noexcept {
  if (landed(p, c, back_on_top, false)) return;
  // a wall pushes back against the search
  if (-(p.force_n.x * dir_x_ + p.force_n.y * dir_y_) > params_.touch_n) {
    wall_ns_ = now_ns_;
    return enter(Phase::climb);
  }
  // one side, then the other (twice as far: back past the start), then back along the route
  phase_travel_m_ += params_.search_m_per_s * period_s_;
  const double leg = search_leg_ == 1 ? 2.0 * params_.search_m : params_.search_m;
  if (phase_travel_m_ >= leg) {
    phase_travel_m_ = 0.0;
    ++search_leg_;
    if (search_leg_ == 1) {
      dir_x_ = -dir_x_;
      dir_y_ = -dir_y_;
    } else if (search_leg_ == 2) {
      dir_x_ = -heading_x();
      dir_y_ = -heading_y();
    } else {
      return enter(Phase::reposition);
    }
  }
  const double vz = (support_z_m_ - target_to_.z) / kHoldTime_s;
  move(params_.search_m_per_s * dir_x_, params_.search_m_per_s * dir_y_, vz);
}

void VirtualSubject::climb(const Percept& p, const Contact& c, bool back_on_top) noexcept {
  if (landed(p, c, back_on_top, true)) return;
  // up the wall, pushing against it, until it is no longer felt
  const bool wall = -(p.force_n.x * dir_x_ + p.force_n.y * dir_y_) > 0.5 * params_.touch_n;
  if (wall) wall_ns_ = now_ns_;
  if (static_cast<double>(now_ns_ - wall_ns_) * 1e-9 > kWallGone_s) {
    if (p.handle_m.z >= top_z_m_ - params_.drop_m) return enter(Phase::over);
    support_z_m_ = p.handle_m.z;
    return enter(Phase::search);  // slipped off the wall: look again
  }
  // no higher than a little above the top as remembered
  const double vz = std::min(params_.climb_m_per_s, (top_z_m_ + kAboveTop_m - target_to_.z) / period_s_);
  move(0.0, 0.0, vz);
  const double into = params_.push_n / stiffness_n_per_m_;
  target_to_.x = p.handle_m.x + dir_x_ * into;
  target_to_.y = p.handle_m.y + dir_y_ * into;
}

void VirtualSubject::over(const Percept& p, const Contact& c, bool back_on_top) noexcept {
  if (landed(p, c, back_on_top, true)) return;
  phase_travel_m_ += params_.search_m_per_s * period_s_;
  if (phase_travel_m_ >= params_.over_m) return enter(Phase::descend);
  move(params_.search_m_per_s * dir_x_, params_.search_m_per_s * dir_y_, (top_z_m_ + kAboveTop_m - target_to_.z) / kHoldTime_s);
}

void VirtualSubject::reposition() noexcept {
  // the experimenter lifts the hand above the bridge, takes it to the start, lets go
  target_from_ = target_to_;
  from_ns_ = now_ns_;
  const double step = kRepositionSpeed_m_per_s * period_s_;
  const double up_z = std::max(start_m_.z, top_z_m_ + 0.002);
  if (target_to_.z < up_z) {
    target_to_.z = std::min(up_z, target_to_.z + step);
    return;
  }
  const double dx = start_m_.x - target_to_.x, dy = start_m_.y - target_to_.y;
  const double d = std::hypot(dx, dy);
  if (d > step) {
    target_to_.x += dx / d * step;
    target_to_.y += dy / d * step;
    return;
  }
  target_to_ = {start_m_.x, start_m_.y, up_z};
  segment_ = 0;
  segment_travel_m_ = turn_rad_ = 0.0;
  side_cue_ = 0.0;
  lost_ = false;
  enter(Phase::settle);
}

}  // namespace enact::devices
