// Ctrl-C / SIGTERM: the first asks the render to stop after its current batch (the image so far is
// written); a second one exits at once. announce: say so on stderr (MPI ranks other than 0 do not).
#pragma once
#include <atomic>

namespace bp {

void install_interrupt_handlers(bool announce = true);
const std::atomic<bool>& stop_requested();

}  // namespace bp
