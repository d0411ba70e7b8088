#pragma once
#include "scheduler/sqlite_db.h"

namespace pathfarm::farm {

// Brings the database to the newest schema, one numbered migration at a time, each in
// its own transaction. A database from a newer pathfarm is refused. `upTo` (tests of a
// migration) stops at that version instead.
void migrate(Database& db, int upTo = 0);
int schemaVersion(Database& db);

// Task states in the tasks table.
enum class TaskState : int { Waiting = 0, Ready = 1, Leased = 2, Done = 3, Failed = 4 };
// Attempt states in the attempts table.
enum class AttemptState : int { Running = 0, Done = 1, Failed = 2, Expired = 3, Revoked = 4 };

}  // namespace pathfarm::farm
