#include "physics/mujoco_world.hpp"

#include <mujoco/mujoco.h>

#include <array>

#include "physics/mjcf_world.hpp"

namespace dxlemu::physics {
namespace {

// mj_loadXML's error buffer: MuJoCo's messages are one line.
constexpr std::size_t kErrorLength = 1024;

// MuJoCo's default handlers print, write MUJOCO_LOG.TXT into the working directory, and on an
// error exit the process. dxlemu reports errors itself and keeps warnings off the terminal the
// client's session may share; a warning that matters (an unstable model) shows in the motion.
void on_mujoco_error(const char* message) {
  throw PhysicsError(std::string("MuJoCo: ") + message);
}

void on_mujoco_warning(const char* /*message*/) {}

void install_handlers() {
  mju_user_error = on_mujoco_error;
  mju_user_warning = on_mujoco_warning;
}

bool one_dof(int type) {
  return type == mjJNT_HINGE || type == mjJNT_SLIDE;
}

}  // namespace

MujocoWorld::MujocoWorld(const std::filesystem::path& file, double timestep_s) {
  install_handlers();
  std::array<char, kErrorLength> error{};
  model_ = mj_loadXML(file.c_str(), nullptr, error.data(), static_cast<int>(error.size()));
  if (model_ == nullptr) {
    throw PhysicsError(std::string("MuJoCo cannot load it: ") + error.data());
  }
  model_->opt.timestep = timestep_s;
  data_ = mj_makeData(model_);
  if (data_ == nullptr) {
    mj_deleteModel(model_);
    throw PhysicsError("MuJoCo cannot allocate its data");
  }
  // Positions and velocities of the initial state, before the first step.
  mj_forward(model_, data_);
}

MujocoWorld::~MujocoWorld() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

std::string MujocoWorld::engine() {
  return std::string("MuJoCo ") + mj_versionString();
}

std::optional<std::size_t> MujocoWorld::find_joint(std::string_view name) const {
  const std::string key(name);
  const int id = mj_name2id(model_, mjOBJ_JOINT, key.c_str());
  if (id < 0 || !one_dof(model_->jnt_type[id])) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(id);
}

std::string MujocoWorld::joint_names() const {
  std::string out;
  for (int j = 0; j < model_->njnt; ++j) {
    const char* name = mj_id2name(model_, mjOBJ_JOINT, j);
    if (name == nullptr || !one_dof(model_->jnt_type[j])) {
      continue;
    }
    out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out.empty() ? "none" : out;
}

double MujocoWorld::timestep_s() const {
  return model_->opt.timestep;
}

void MujocoWorld::add_armature(std::size_t joint, double kg_m2) {
  model_->dof_armature[model_->jnt_dofadr[joint]] += kg_m2;
}

void MujocoWorld::set_torque(std::size_t joint, double torque_nm) {
  data_->qfrc_applied[model_->jnt_dofadr[joint]] = torque_nm;
}

void MujocoWorld::step() {
  mj_step(model_, data_);
}

JointState MujocoWorld::joint(std::size_t joint) const {
  return {data_->qpos[model_->jnt_qposadr[joint]], data_->qvel[model_->jnt_dofadr[joint]]};
}

}  // namespace dxlemu::physics
