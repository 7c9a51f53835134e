#include "core/signal_actions.hpp"

namespace softcut {

KeepSignalActions::KeepSignalActions() {
  sigaction(SIGINT, nullptr, &int_);
  sigaction(SIGTERM, nullptr, &term_);
}

KeepSignalActions::~KeepSignalActions() {
  sigaction(SIGINT, &int_, nullptr);
  sigaction(SIGTERM, &term_, nullptr);
}

}  // namespace softcut
