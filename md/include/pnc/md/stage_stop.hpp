#pragma once
// pnc/md/stage_stop.hpp: stage children that end when pnc is asked to stop.
//
// A stop request (pnc::process_stop(), set by SIGINT/SIGTERM in the application) reaches the
// forked stage children through the token's shared mapping. stoppable() wraps a stage body so
// that, in the child: SIGINT/SIGTERM take their default action again (a Ctrl-C to the process
// group ends the child), a stage started after the request ends at once, and a watcher thread
// ends the child with SIGTERM when the request comes while LAMMPS runs. Every file a stage
// writes is written atomically or named by a checkpoint only once whole (deform.cpp,
// equilibrate.cpp), so the last checkpoint stays valid and --resume continues from it. The
// parent calls pnc::throw_if_stopped() when run_stage(s) returns, before judging the outcomes.
#include "pnc/md/runner.hpp"

namespace pnc::md {

/// `body`, ending early on a stop request as above.
StageBody stoppable(StageBody body);

} // namespace pnc::md
