#pragma once
// A virtual subject: a synthetic user that holds a simulated force-feedback device and
// follows the bridge task's instructions (Khatchatourov et al. 2009): make small movements
// to stay on the top surface and move along it; when contact is lost, move sideways to find
// a wall, follow it up, and get back on the top. It is a test driver and a baseline for the
// experiment runner, not a model of human data.
//
// What it perceives is what a person would: where its hand is, the force the handle pushes
// the hand with, and the pins under its fingertip as the tactile device shows them (after
// the cells' rise time), all with a reaction delay. It never sees the physical model. Its
// output is the hand's target (the device's hand impedance pulls the handle towards it),
// with signal-dependent motor noise (Harris & Wolpert, Nature 1998: the noise grows with
// the command): velocity noise of sd motor_noise * commanded speed + a floor, low-pass
// filtered with the time constant noise_time_s.
//
// The pins: before it moves, the subject notes what the pins show in the air; a pin that
// shows otherwise afterwards signals contact under it. So inverted pins (CM3) are read too,
// though less well: inverted_pin_use scales their use (an assumption of this baseline). tactile_use in [0, 1] scales how much the pins
// steer it (0: ignored, also as contact evidence).
//
// The route: it remembers the bridge as headings and lengths (from its file, as a person
// told the shape or shown it in practice), each trial with errors whose sd shrinks to 0 as
// route_memory goes to 1. It travels a segment by its own motor commands (efference copy),
// so motor noise makes it drift; the pins correct the drift, the force alone cannot until
// the hand falls. Lost past finding a wall for reposition_after_s, it is put back at the
// start (as the experimenter did) and starts again.
//
// Determinism: subject_seed draws the subject's traits (speed, delay and noise factors
// across subjects), noise_seed its motor noise and memory errors; reset() restarts both, so
// the same calls give the same targets. target() allocates nothing and never throws.
#include <cstdint>
#include <string>
#include <vector>

#include "core/devices/hand.h"
#include "core/math/random.h"

namespace enact::devices {

struct SubjectParams {
  std::string name = "virtual";
  // moving
  double speed_m_per_s = 0.010;          // along the route on the top
  double press_n = 0.8;                  // pressing down on the top
  double descend_m_per_s = 0.010;        // lowering onto a surface
  double search_m_per_s = 0.015;         // sideways when lost, looking for a wall
  double climb_m_per_s = 0.030;          // up a wall
  double push_n = 0.4;                   // against a wall while climbing it
  double search_m = 0.008;               // sideways before trying the other side
  double over_m = 0.004;                 // over the top after climbing a wall
  double settle_s = 0.3;                 // still at the start before moving (and after a reposition); at least the reaction delay + 50 ms
  double reposition_after_s = 4.0;       // lost this long: put back at the start
  // sensing
  double touch_n = 0.15;                 // a force felt as contact
  double drop_m = 0.001;                 // this far below the last contact, with no contact: fallen
  double reaction_delay_s = 0.15;        // every percept is this old (0 .. 1 s)
  double control_period_s = 0.001;       // how often the subject updates its intention
  double pin_pitch_m = 0.00245;          // the spacing of the pins under the fingertip
  double tactile_use = 1.0;              // 0 .. 1: how much the pins count
  double tactile_gain_per_s = 3.0;       // sideways speed per metre of contact-centroid offset across the heading
  double tactile_turn_per_s_m = 150.0;   // turning rate (rad/s) per metre of that offset
  double inverted_pin_use = 0.5;         // 0 .. 1: how well it reads pins that rise off contact (CM3), relative to on contact
  // noise
  double motor_noise = 0.3;              // velocity noise sd per unit commanded speed
  double motor_noise_floor_m_per_s = 0.0005;
  double noise_time_s = 0.1;             // correlation time of the motor noise
  // the route as remembered: headings in degrees from forward (+y) to the right (+x)
  double route_memory = 0.3;             // 0 .. 1: 1 remembers exactly
  std::vector<double> route_headings_deg{45.0, -45.0, 45.0};
  std::vector<double> route_lengths_m{0.021, 0.021, 0.021};
  double heading_error_deg = 35.0;       // sd of a remembered heading's error at route_memory 0
  double length_error = 0.3;             // sd of a remembered length's error (fraction) at route_memory 0
  // between subjects: sd (fraction) of one subject's speed, reaction delay and noise factors
  double between_subjects = 0.15;
};

// read a subject file (YAML, docs/experiments.md "Virtual subjects"); unknown keys and bad values
// throw config::Error with file:line and the fix
SubjectParams load_subject(const std::string& path);
// the same checks on params built in code; `source` names them in messages
void validate(const SubjectParams& params, const std::string& source);

class VirtualSubject final : public HandSource {
 public:
  // one subject (traits drawn from subject_seed) for trials with noise from noise_seed;
  // validates the params (config::Error) and allocates everything target() needs
  VirtualSubject(SubjectParams params, std::uint64_t subject_seed, std::uint64_t noise_seed);

  void reset(const HandStart& start) noexcept override;
  math::Vec3 target(std::int64_t time_ns, const HandFeel& feel) noexcept override;
  bool feels_pins() const override { return true; }
  void feel_pins(const float* levels, int rows, int cols) noexcept override;

  // what the subject is doing
  enum class Phase : std::uint8_t { settle, descend, follow, search, climb, over, reposition };
  Phase phase() const { return phase_; }
  // times it fell off (entered search) and was put back at the start, since reset
  int losses() const { return losses_; }
  int repositions() const { return repositions_; }
  // the traits of this subject after the between-subject draw
  double speed_m_per_s() const { return speed_m_per_s_; }
  double reaction_delay_s() const { return delay_s_; }
  const SubjectParams& params() const { return params_; }

 private:
  struct Percept {
    math::Vec3 handle_m;
    math::Vec3 force_n;
    std::uint32_t pins_up = 0;  // bit i: pin i shown above half stroke
  };
  // the evidence of contact in one percept
  struct Contact {
    bool force_up = false;   // pushed up by a surface
    int pins = 0;            // pins that differ from the air reference
    double cx_m = 0.0;       // centroid of those pins, grid frame (x right, y forward)
    double cy_m = 0.0;
    bool touching() const { return force_up || pins > 0; }
  };

  // one control step: remember `now`, act on the percept a reaction delay old (one function
  // a phase below)
  void control(const Percept& now) noexcept;
  void settle(const Percept& p) noexcept;
  void descend(const Percept& p, const Contact& c) noexcept;
  void follow(const Percept& p, const Contact& c) noexcept;
  void search(const Percept& p, const Contact& c, bool back_on_top) noexcept;
  void climb(const Percept& p, const Contact& c, bool back_on_top) noexcept;
  void over(const Percept& p, const Contact& c, bool back_on_top) noexcept;
  void reposition() noexcept;
  // back on the top while searching, climbing or going over: follow again (true)
  bool landed(const Percept& p, const Contact& c, bool back_on_top, bool need_force) noexcept;
  // the evidence of contact in a percept
  Contact contact(const Percept& p) const noexcept;
  void enter(Phase phase) noexcept;
  // the heading now: the remembered one of the segment, turned by what the pins said
  double heading_x() const noexcept;
  double heading_y() const noexcept;
  // fallen: look for a wall on the side the bridge most likely is
  void start_search(const Percept& p) noexcept;
  // a velocity command into the next target, with motor noise on the horizontal
  void move(double vx, double vy, double vz) noexcept;
  // on the top: remember where, how high, and where the pins say the bridge is
  void on_top(const Percept& p, const Contact& c) noexcept;

  SubjectParams params_;
  std::uint64_t noise_seed_;
  math::Random noise_;
  // traits
  double speed_m_per_s_ = 0.0;
  double delay_s_ = 0.0;
  double noise_factor_ = 1.0;
  std::int64_t period_ns_ = 0;
  double period_s_ = 0.0;
  int delay_ticks_ = 0;
  double stiffness_n_per_m_ = 300.0;
  math::Vec3 start_m_;
  // the percepts of the last reaction delay: ring buffer, the newest at head_
  std::vector<Percept> percepts_;
  std::size_t head_ = 0;
  std::uint32_t pins_up_now_ = 0;
  int pin_rows_ = 0;
  int pin_cols_ = 0;
  std::uint32_t air_pins_ = 0;   // what the pins show in the air
  bool air_known_ = false;
  double tactile_use_ = 0.0;     // tactile_use, less for inverted pins
  // the route as remembered this trial
  std::vector<double> heading_x_, heading_y_, length_m_;
  std::size_t segment_ = 0;
  double segment_travel_m_ = 0.0;  // along the segment's heading, by efference copy
  double turn_rad_ = 0.0;          // turned from the remembered heading (+: to the right)
  // the intention: the target moves from target_from_ (at from_ns_) to target_to_ (one period later)
  std::int64_t next_control_ns_ = 0;
  std::int64_t from_ns_ = 0;
  math::Vec3 target_from_;
  math::Vec3 target_to_;
  math::Vec3 noise_m_per_s_;
  // the phase and its memory
  Phase phase_ = Phase::settle;
  std::int64_t phase_ns_ = 0;        // when the phase began
  std::int64_t now_ns_ = 0;
  bool lost_ = false;                // fell off and not yet back on the top
  std::int64_t lost_at_ns_ = 0;      // when the current loss began (search entered)
  std::int64_t wall_ns_ = 0;         // when a wall was last felt while climbing
  double support_z_m_ = 0.0;         // hand height at the last contact from below
  double top_z_m_ = 0.0;             // hand height on the top, as felt
  bool top_known_ = false;
  double last_top_x_m_ = 0.0, last_top_y_m_ = 0.0;  // hand position at the last contact on the top
  double side_cue_ = 0.0;            // the pins' last hint of where the bridge is, across the heading (m, + right)
  double dir_x_ = 0.0, dir_y_ = 0.0; // search / climb / over direction
  double phase_travel_m_ = 0.0;      // how far the search or over has gone
  int search_leg_ = 0;               // 0: first side, 1: the other side, 2: back along the route
  int losses_ = 0;
  int repositions_ = 0;
};

}  // namespace enact::devices
