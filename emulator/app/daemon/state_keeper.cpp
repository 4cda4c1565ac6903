#include "app/daemon/state_keeper.hpp"

#include <utility>

#include "app/daemon/log.hpp"

namespace dxlemu::app {

StateKeeper::StateKeeper(std::optional<std::filesystem::path> file, BusState saved, Writer write)
    : file_(std::move(file)), write_(std::move(write)), saved_(std::move(saved)) {}

StateKeeper StateKeeper::open(const std::optional<std::filesystem::path>& file, Writer write) {
  return {file, file ? read_state(*file) : BusState{}, std::move(write)};
}

void StateKeeper::add_port(std::string port, bus::Bus& bus) {
  ports_.push_back({std::move(port), &bus});
}

void StateKeeper::restore() {
  for (const Port& port : ports_) {
    const auto it = saved_.find(port.name);
    const auto& servos = port.bus->servos();
    for (std::size_t i = 0; i < servos.size(); ++i) {
      model::Servo& servo = *servos[i];
      if (it != saved_.end() && i < it->second.size()) {
        const ServoState& saved = it->second[i];
        if (saved.model == servo.spec().name) {
          restore_state(servo.table(), saved, file_->string(),
                        "/ports/" + port.name + "/" + std::to_string(i));
        } else {
          log(LogLevel::Warn, file_->string() + ": " + port.name + " servo " + std::to_string(i) +
                                  " was a " + saved.model + ", now a " + servo.spec().name +
                                  ": it starts from its config");
        }
      }
      servo.commit_deferred();  // the ID, baud and protocol of the config and the state apply
    }
  }
  save_if_changed();
}

void StateKeeper::save_if_changed() {
  if (!file_) {
    return;
  }
  // Called on every PTY read: while no EEPROM byte has changed since the last look, there is
  // nothing to compare.
  std::uint64_t changes = 0;
  for (const Port& port : ports_) {
    for (const auto& servo : port.bus->servos()) {
      changes += servo->table().eeprom_changes();
    }
  }
  if (checked_eeprom_changes_ == changes) {
    return;
  }
  // A byte may have changed and changed back: the images decide, as they always did.
  std::vector<std::vector<std::uint8_t>> images;
  for (const Port& port : ports_) {
    for (const auto& servo : port.bus->servos()) {
      images.push_back(eeprom_image(servo->table()));
    }
  }
  if (images == saved_eeprom_) {  // empty at first: the first call always writes
    checked_eeprom_changes_ = changes;
    return;
  }
  BusState state;
  for (const Port& port : ports_) {
    auto& list = state[port.name];
    for (const auto& servo : port.bus->servos()) {
      list.push_back(capture_state(servo->table()));
    }
  }
  write_(*file_, state_to_text(state));
  saved_eeprom_ = std::move(images);
  checked_eeprom_changes_ = changes;
  log(LogLevel::Debug, "saved the EEPROM of every servo to " + file_->string());
}

}  // namespace dxlemu::app
