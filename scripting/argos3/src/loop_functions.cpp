// The ARGoS loop functions host and the space as ARGoS loop functions see
// it: foot-bot views over Colony's space, read when asked.
#include "argos3/core/simulator/loop_functions.h"

#include "configuration_tree.h"
#include "core/log.h"
#include "core/simulation.h"

namespace argos {

namespace {

const colony::Space& SpaceOf(const internal::EntityLink& link) { return link.simulation->space(); }

// The slot of the linked entity; throws when it was removed.
uint32_t Slot(const internal::EntityLink& link) {
  const colony::EntityHandle handle{link.index, link.generation};
  if (!SpaceOf(link).IsAlive(handle))
    THROW_ARGOSEXCEPTION("entity \"" << link.id << "\" no longer exists");
  return link.index;
}

}  // namespace

CLoopFunctions::~CLoopFunctions() = default;

const SAnchor& CEmbodiedEntity::GetOriginAnchor() const {
  const colony::Pose& pose = SpaceOf(link_).pose(Slot(link_));
  origin_.Id = "origin";
  origin_.Position.Set(pose.position.x(), pose.position.y(), pose.position.z());
  origin_.Orientation.Set(pose.orientation.w(), pose.orientation.x(), pose.orientation.y(),
                          pose.orientation.z());
  return origin_;
}

CCI_Controller& CControllableEntity::GetController() {
  const uint32_t slot = Slot(link_);
  colony::Controller* controller = link_.simulation->ControllerOf(SpaceOf(link_).HandleOf(slot));
  auto* host = dynamic_cast<internal::ControllerHost*>(controller);
  if (host == nullptr || host->user() == nullptr) {
    THROW_ARGOSEXCEPTION("robot \"" << link_.id
                                    << "\" does not run an ARGoS controller (REGISTER_CONTROLLER), "
                                       "so GetController() cannot give a CCI_Controller");
  }
  return *host->user();
}

const std::string& CControllableEntity::GetId() const { return link_.id; }

CLEDEntity& CLEDEquippedEntity::GetLED(UInt32 index) {
  const auto leds = SpaceOf(link_).leds(Slot(link_));
  if (index >= leds.size()) {
    THROW_ARGOSEXCEPTION("robot \"" << link_.id << "\" has no LED " << index << "; it has "
                                    << leds.size());
  }
  const colony::Color c = leds[index];
  led_.color_ = CColor(c.r, c.g, c.b, c.a);
  return led_;
}

CSpace::CSpace(colony::Simulation& simulation) : simulation_(simulation) {
  const colony::Space& space = simulation.space();
  const colony::Vec3 min = space.arena_min(), max = space.arena_max();
  arena_size_.Set(max.x() - min.x(), max.y() - min.y(), max.z() - min.z());
  arena_center_.Set((max.x() + min.x()) / 2, (max.y() + min.y()) / 2, (max.z() + min.z()) / 2);
  arena_limits_.Set(CVector3(min.x(), min.y(), min.z()), CVector3(max.x(), max.y(), max.z()));
}

CSpace::~CSpace() = default;

UInt32 CSpace::GetSimulationClock() const { return static_cast<UInt32>(simulation_.tick()); }

CSpace::TMapPerType& CSpace::GetEntitiesByType(const std::string& type) {
  return const_cast<TMapPerType&>(std::as_const(*this).GetEntitiesByType(type));
}

const CSpace::TMapPerType& CSpace::GetEntitiesByType(const std::string& type) const {
  if (type != "foot-bot" && type != "marxbot") {
    THROW_ARGOSEXCEPTION("GetEntitiesByType(\"" << type
                                                << "\"): Colony's ARGoS compatibility "
                                                   "layer gives loop functions \"foot-bot\" "
                                                   "entities only");
  }
  Refresh();
  return footbot_map_;
}

// Rebuilds the map when the robots alive changed since the last call; the
// views of robots still alive are kept.
void CSpace::Refresh() const {
  const colony::Space& space = simulation_.space();
  std::vector<UInt32> alive;
  for (size_t t = 0; t < space.type_count(); ++t) {
    if (space.TypeLabel(static_cast<uint16_t>(t)) != "marxbot") continue;
    for (uint32_t slot : space.OfType(static_cast<uint16_t>(t)))
      if (space.alive(slot) && (space.flags(slot) & colony::kRobot)) alive.push_back(slot);
  }
  bool same = alive == listed_;
  for (size_t i = 0; same && i < alive.size(); ++i)
    same = space.HandleOf(alive[i]).generation == generations_[alive[i]];
  if (same) return;
  if (footbots_.size() < space.slots()) {
    footbots_.resize(space.slots());
    generations_.resize(space.slots());
  }
  footbot_map_.clear();
  for (UInt32 slot : alive) {
    auto& view = footbots_[slot];
    const colony::EntityHandle handle = space.HandleOf(slot);
    if (!view || generations_[slot] != handle.generation) {
      view = std::make_unique<CFootBotEntity>(
          internal::EntityLink{&simulation_, slot, handle.generation, space.id(slot)});
      generations_[slot] = handle.generation;
    }
    footbot_map_[view->GetId()] = view.get();
  }
  listed_ = std::move(alive);
}

namespace internal {

LoopFunctionsHost::LoopFunctionsHost(Factory factory, bool draws_floor)
    : factory_(factory), draws_floor_(draws_floor) {}

LoopFunctionsHost::~LoopFunctionsHost() = default;

void LoopFunctionsHost::Init(const colony::Params& params) {
  stream_ = colony::RandomStream::For(sim().seed(), "loop_functions", "argos");
  space_ = std::make_unique<CSpace>(sim());
  OwnerScope scope(this);
  user_ = factory_();
  user_->space_ = space_.get();
  bool first_reader = false;
  TConfigurationNode tree =
      BuildConfigurationTree("loop_functions", TakeParameters(params, first_reader));
  try {
    user_->Init(tree);
  } catch (const CARGoSException& e) {
    if (e.parameter().empty()) throw;
    throw ToParamError(e, tree);
  }
  const CLoopFunctions& user = *user_;
  for (const auto& name : UnreadAttributes(tree)) {
    colony::LogWarning("ARGoS loop functions " + TypeName(typeid(user)) +
                       " do not read parameter '" + name + "' (ignored)");
  }
}

void LoopFunctionsHost::PreStep() {
  OwnerScope scope(this);
  user_->PreStep();
}

void LoopFunctionsHost::PostStep() {
  OwnerScope scope(this);
  user_->PostStep();
}

bool LoopFunctionsHost::IsExperimentFinished() {
  OwnerScope scope(this);
  return user_->IsExperimentFinished();
}

colony::Color LoopFunctionsHost::FloorColor(double x, double y) {
  OwnerScope scope(this);
  const CColor c = user_->GetFloorColor(CVector2(x, y));
  return {c.GetRed(), c.GetGreen(), c.GetBlue(), c.GetAlpha()};
}

void LoopFunctionsHost::Destroy() {
  if (!user_ || destroyed_) return;
  destroyed_ = true;
  OwnerScope scope(this);
  user_->PostExperiment();
  user_->Destroy();
}

void LoopFunctionsHost::Keep(std::unique_ptr<CRandom::CRNG> rng) {
  rngs_.push_back(std::move(rng));
}

}  // namespace internal
}  // namespace argos
