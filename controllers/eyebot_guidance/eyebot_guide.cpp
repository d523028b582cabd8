// eyebot_guide: the eye-bot's part in the guidance experiment
// (experiments/eyebot_guidance.xml). It flies straight up to the ceiling and
// holds on; it then searches the floor with its pan-tilt camera, a full turn
// of pan at each of a few tilts, for a blob of the target's colour; found, it
// keeps the camera, and with it the laser, pointed at the blob, the laser on,
// so the spot marks the target for the foot-bots. A search that finds
// nothing sends it to another place under the ceiling, chosen at random in
// `area`, to search again.
//   params: target_color (a colour, default 0,0,255), color_tolerance (per
//           channel, 60), climb_speed (m/s, 0.5), tilts (degrees, the search's
//           tilts, "25,50,75"), pan_step (degrees, 60), area ("x0,y0,x1,y1",
//           m, where to search next; default -2,-2,2,2), lost_steps (20: for
//           how many control steps a marked target may be out of sight
//           before it searches again)
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "actuators/eyebot_ceiling/eyebot_ceiling.h"
#include "actuators/eyebot_laser/eyebot_laser.h"
#include "actuators/eyebot_pan_tilt/eyebot_pan_tilt.h"
#include "actuators/eyebot_propulsion/eyebot_propulsion.h"
#include "core/color.h"
#include "core/registry.h"
#include "sensors/eyebot_ceiling/eyebot_ceiling.h"
#include "sensors/eyebot_pan_tilt_camera/eyebot_pan_tilt_camera.h"
#include "sensors/positioning/positioning.h"

namespace colony {
namespace {

class EyebotGuide : public Controller {
 public:
  void Init(const Params& params) override {
    const std::string color = params.GetString("target_color", "0,0,255");
    const std::optional<Color> target = ParseColor(color);
    if (!target) {
      throw ParamError(
          "target_color", color,
          "parameter 'target_color': '" + color + "' is not a colour; accepted: " + kColorAccepted);
    }
    target_color_ = {double(target->r), double(target->g), double(target->b)};
    tolerance_ = params.GetDouble("color_tolerance", 60, 0, 255);
    climb_speed_ = params.GetDouble("climb_speed", 0.5, 0.01, 10);
    for (double t : params.GetNumbers("tilts", "25,50,75", 0, 0, 90))
      tilts_.push_back(t * M_PI / 180);
    pan_step_ = params.GetDouble("pan_step", 60, 1, 360) * M_PI / 180;
    const auto area = params.GetNumbers("area", "-2,-2,2,2", 4);
    if (area[0] >= area[2] || area[1] >= area[3]) {
      throw ParamError("area", params.GetString("area", ""),
                       "parameter 'area': x0 < x1 and y0 < y1 needed");
    }
    area_ = {area[0], area[1], area[2], area[3]};
    lost_steps_ = static_cast<int>(params.GetInt("lost_steps", 20, 0, 1000000));
    position_ = &GetSensor<PositioningSensor>("positioning");
    ceiling_ = &GetSensor<EyebotCeilingSensor>("eyebot_ceiling");
    camera_ = &GetSensor<EyebotPanTiltCamera>("eyebot_pan_tilt_camera");
    rotors_ = &GetActuator<EyebotPropulsionActuator>("eyebot_propulsion");
    hold_ = &GetActuator<EyebotCeilingActuator>("eyebot_ceiling");
    head_ = &GetActuator<EyebotPanTiltActuator>("eyebot_pan_tilt");
    laser_ = &GetActuator<EyebotLaserActuator>("eyebot_laser");
    Reset();
  }

  void Reset() override {
    state_ = State::kClimb;
    scan_tilt_ = 0;
    scan_turns_ = 0;
    since_seen_ = 0;
  }

  void ControlStep() override {
    switch (state_) {
      case State::kClimb:
        Climb();
        break;
      case State::kSearch:
        Search();
        break;
      case State::kMark:
        Mark();
        break;
      case State::kMove:
        Move();
        break;
    }
  }

  // For tests and loop functions: whether it points its laser at a target.
  bool marking() const { return state_ == State::kMark; }

 private:
  enum class State { kClimb, kSearch, kMark, kMove };

  void Climb() {
    laser_->Off();
    hold_->Attach();  // holds on as soon as its top touches the ceiling
    if (ceiling_->attached()) {
      rotors_->Off();
      StartSearch();
      return;
    }
    rotors_->SetVelocity(0, 0, climb_speed_);
  }

  void StartSearch() {
    state_ = State::kSearch;
    scan_tilt_ = 0;
    scan_turns_ = 0;
    head_->SetTilt(tilts_[0]);
    head_->SetPan(camera_->pan());
  }

  // One pan step at a time: the next once the head has reached the last.
  void Search() {
    if (const auto* blob = TargetBlob()) {
      PointAt(*blob);
      laser_->On();
      state_ = State::kMark;
      since_seen_ = 0;
      return;
    }
    const bool there =
        std::abs(std::remainder(camera_->pan() - head_->target_pan(), 2 * M_PI)) < 0.01 &&
        std::abs(camera_->tilt() - head_->target_tilt()) < 0.01;
    if (!there) return;
    if (++scan_turns_ * pan_step_ <= 2 * M_PI + 1e-9) {
      head_->SetPan(head_->target_pan() + pan_step_);
      return;
    }
    scan_turns_ = 0;
    if (++scan_tilt_ < tilts_.size()) {
      head_->SetTilt(tilts_[scan_tilt_]);
      return;
    }
    // Nothing here: search from elsewhere.
    state_ = State::kMove;
    hold_->Detach();
    destination_ = {area_[0] + (area_[2] - area_[0]) * rng().Uniform(),
                    area_[1] + (area_[3] - area_[1]) * rng().Uniform()};
    rotors_->SetTargetPosition(destination_[0], destination_[1], position_->z() - 0.3);
  }

  void Mark() {
    if (const auto* blob = TargetBlob()) {
      PointAt(*blob);
      since_seen_ = 0;
      return;
    }
    if (++since_seen_ > lost_steps_) {
      laser_->Off();
      StartSearch();
    }
  }

  void Move() {
    const double dx = position_->x() - destination_[0], dy = position_->y() - destination_[1];
    if (std::hypot(dx, dy) < 0.05) state_ = State::kClimb;
  }

  // The camera (and laser) straight at `blob`.
  void PointAt(const EyebotPanTiltCamera::Blob& blob) {
    head_->SetPan(blob.bearing);
    head_->SetTilt(std::clamp(M_PI / 2 + blob.elevation, 0.0, M_PI / 2));
  }

  // The blob of the target's colour nearest the camera's axis, or nullptr.
  const EyebotPanTiltCamera::Blob* TargetBlob() const {
    const EyebotPanTiltCamera::Blob* best = nullptr;
    double best_offset = 0;
    const double pan = camera_->pan(), tilt = camera_->tilt();
    for (const auto& b : camera_->blobs()) {
      if (std::abs(b.red - target_color_[0]) > tolerance_ ||
          std::abs(b.green - target_color_[1]) > tolerance_ ||
          std::abs(b.blue - target_color_[2]) > tolerance_)
        continue;
      const double offset = std::abs(std::remainder(b.bearing - pan, 2 * M_PI)) +
                            std::abs(M_PI / 2 + b.elevation - tilt);
      if (!best || offset < best_offset) {
        best = &b;
        best_offset = offset;
      }
    }
    return best;
  }

  State state_ = State::kClimb;
  std::array<double, 3> target_color_{};
  double tolerance_ = 0, climb_speed_ = 0, pan_step_ = 0;
  int lost_steps_ = 0, since_seen_ = 0;
  std::vector<double> tilts_;
  size_t scan_tilt_ = 0;
  int scan_turns_ = 0;
  std::array<double, 4> area_{};
  std::array<double, 2> destination_{};
  const PositioningSensor* position_ = nullptr;
  const EyebotCeilingSensor* ceiling_ = nullptr;
  const EyebotPanTiltCamera* camera_ = nullptr;
  EyebotPropulsionActuator* rotors_ = nullptr;
  EyebotCeilingActuator* hold_ = nullptr;
  EyebotPanTiltActuator* head_ = nullptr;
  EyebotLaserActuator* laser_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    EyebotGuide, "eyebot_guide",
    "the eye-bot of the guidance experiment: climbs to the ceiling, searches the floor with its "
    "pan-tilt camera for a blob of target_color, and points its laser at it",
    {{"target_color", "a colour (a name or \"r,g,b\")", "0,0,255",
      "colour of the blob to point the laser at"},
     {"color_tolerance", "a number in [0, 255]", "60",
      "largest difference per channel from target_color"},
     {"climb_speed", "a number in [0.01, 10] (m/s)", "0.5", "speed up to the ceiling"},
     {"tilts", "numbers in [0, 90] separated by commas (degrees)", "25,50,75",
      "the head's tilts while searching"},
     {"pan_step", "a number in [1, 360] (degrees)", "60", "pan between two search views"},
     {"area", "\"x0,y0,x1,y1\" (m), x0 < x1, y0 < y1", "-2,-2,2,2", "where to search"},
     {"lost_steps", "a whole number >= 0", "20",
      "control steps a lost blob is kept before searching again"}});

}  // namespace
}  // namespace colony
