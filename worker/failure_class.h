#pragma once
// Why a task failed on this worker, as the scheduler needs to know it: a bad input fails
// the task at once and blames no one; a transfer that could not be made runs the task
// again without blaming the worker; anything else is the worker's fault.
#include <exception>
#include <stdexcept>

#include "pathfarm/worker_service.pb.h"

namespace pathfarm::farm {

// The task cannot run on any worker: its lease, parameters or an input chunk make no sense.
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An input chunk could not be fetched for a reason other than the scheduler being away.
class TransferFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The class of an exception a task threw. Scene, mesh, texture, EXR and light-path
// expression errors and invalid arguments are bad input, like BadInput itself.
FailureClass classifyFailure(const std::exception& error);

}  // namespace pathfarm::farm
