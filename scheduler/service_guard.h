#pragma once
// Every RPC body runs inside guarded(): the access token is checked first, and the
// farm's exceptions become gRPC statuses a caller can act on.
#include <grpcpp/grpcpp.h>

#include <stdexcept>

#include "proto/wire/chunk_store.h"
#include "proto/wire/connection.h"
#include "scheduler/planner.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::farm {

template <class Body>
grpc::Status guarded(const SchedulerContext& c, grpc::ServerContext* context, Body&& body) {
  if (!isAuthorized(*context, c.token))
    return {grpc::StatusCode::UNAUTHENTICATED, "refused: this farm requires its access token"};
  try {
    return body();
  } catch (const std::out_of_range& e) {
    return {grpc::StatusCode::NOT_FOUND, e.what()};
  } catch (const PlanError& e) {
    return {grpc::StatusCode::INVALID_ARGUMENT, e.what()};
  } catch (const std::invalid_argument& e) {
    return {grpc::StatusCode::FAILED_PRECONDITION, e.what()};
  } catch (const ChunkError& e) {
    return {grpc::StatusCode::DATA_LOSS, e.what()};
  } catch (const std::exception& e) {
    return {grpc::StatusCode::INTERNAL, e.what()};
  }
}

}  // namespace pathfarm::farm
