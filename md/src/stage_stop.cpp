#include "pnc/md/stage_stop.hpp"

#include "pnc/core/stop.hpp"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

namespace pnc::md {

StageBody stoppable(StageBody body) {
  pnc::StopToken& token = pnc::process_stop(); // created here, in the parent, before the fork
  return [body = std::move(body), &token](Lammps& l) {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    if (token.requested()) throw pnc::Interrupted(token.signal(), "before the stage started");
    std::thread([&token] {
      while (!token.requested())
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      ::kill(::getpid(), SIGTERM); // default action: the whole child ends
    }).detach();
    body(l);
  };
}

} // namespace pnc::md
