#pragma once
// The dashboard on the scheduler's HTTP side: its page (GET /, /app.js, /style.css) and
// its API under /api, JSON read from the same FarmState the gRPC services use, through
// the same functions; actions are POSTs that call what `pathfarm cancel` and its kin call.
// docs/dashboard.md lists the endpoints.
#include "proto/wire/chunk_store.h"
#include "scheduler/farm_clock.h"
#include "scheduler/farm_signal.h"
#include "scheduler/farm_state.h"
#include "scheduler/http/thumbnails.h"

namespace httplib {
class Server;
}

namespace pathfarm::farm {

struct DashboardContext {
  FarmState& state;
  ChunkStore& store;
  FarmSignal& signal;  // woken after an action, as after the same gRPC call
  ThumbnailCache& thumbnails;
};

void serveDashboard(httplib::Server& server, DashboardContext context);

}  // namespace pathfarm::farm
