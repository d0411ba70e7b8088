// libFuzzer target for the scheduler's RPC handlers: any sequence of calls, each any
// request bytes, from a client or worker that may or may not carry the token and its
// session, must be answered with a status that names a reason (never INTERNAL or
// UNKNOWN), and never crash, hang, leak or read out of bounds. Each input runs against a
// fresh farm (an in-memory database, an empty chunk store) and the real WorkerService and
// ClientService (rpc_fuzz_calls.h says how calls reach them). Built and run by
// bench/fuzz.sh (clang, ASan, UBSan).
//
// An input is a list of calls: [call][length, 2 bytes little-endian][request bytes].
// `call` without its bit 0x80, modulo RpcCalls::kCalls, picks the RPC; the bit 0x80 drops
// the token and the session (an outsider). A request that does not parse is sent empty.
// Streams (PutChunk, PutInput) read their request bytes as [length, 2 bytes][ChunkPart
// bytes] parts. Worker calls carry the session of the worker the input registered last.
#include <google/protobuf/stubs/logging.h>
#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz/fuzz_support.h"
#include "fuzz/rpc_fuzz_calls.h"
#include "proto/wire/connection.h"
#include "scheduler/farm_clock.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::fuzz {
namespace {

// A farm small enough that a shot the fuzzer submits plans and lists in microseconds.
farm::ShotLimits fuzzLimits() {
  farm::ShotLimits limits;
  limits.maxFrames = 64;
  limits.maxPixelFrames = 1 << 20;
  limits.maxTasks = 256;
  return limits;
}

// The chunk store's folder: one per process, emptied for every input and removed when the
// process exits (libFuzzer's runs end with exit(), fork mode's children too).
class StoreFolder {
 public:
  StoreFolder() {
    std::string name = (std::filesystem::temp_directory_path() / "pathfarm-rpc-fuzz-XXXXXX").string();
    if (!mkdtemp(name.data())) std::abort();
    path_ = name;
  }
  ~StoreFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

const std::filesystem::path& storeFolder() {
  static const StoreFolder folder;
  return folder.path();
}

// One input's farm: state, store and both services, and an in-process server over them
// once the input calls a stream.
class Farm {
 public:
  Farm()
      : state_(":memory:", farm::FarmSettings{}, farm::farmClockSeconds()),
        store_(freshStore()),
        workers_({state_, store_, signal_, kFuzzToken, fuzzLimits()}),
        clients_({state_, store_, signal_, kFuzzToken, fuzzLimits()}),
        calls_(workers_, clients_, [this] { return channel(); }) {}
  ~Farm() {
    if (!server_) return;
    signal_.notify();  // open watches stop waiting for a change
    server_->Shutdown(std::chrono::system_clock::now());
  }

  RpcCalls& calls() { return calls_; }

 private:
  static std::filesystem::path freshStore() {
    std::filesystem::remove_all(storeFolder());
    std::filesystem::create_directories(storeFolder());
    return storeFolder();
  }
  std::shared_ptr<grpc::Channel> channel() {
    if (channel_) return channel_;
    grpc::ServerBuilder builder;
    farm::configureServer(builder);
    builder.RegisterService(&workers_);
    builder.RegisterService(&clients_);
    server_ = builder.BuildAndStart();
    if (!server_) std::abort();
    channel_ = server_->InProcessChannel(grpc::ChannelArguments());
    return channel_;
  }
  farm::FarmState state_;
  farm::ChunkStore store_;
  farm::FarmSignal signal_;
  farm::WorkerServiceImpl workers_;
  farm::ClientServiceImpl clients_;
  std::unique_ptr<grpc::Server> server_;
  std::shared_ptr<grpc::Channel> channel_;
  RpcCalls calls_;
};

}  // namespace
}  // namespace pathfarm::fuzz

// Each input opens a database: with ASan's default quarantine (256 MB of freed memory
// kept poisoned) and 4 KiB fill of every allocation, SQLite's allocations took most of
// the time of an input.
extern "C" const char* __asan_default_options() { return "quarantine_size_mb=16:max_malloc_fill_size=0"; }

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pathfarm::fuzz::silenceLogs();
  // gRPC's logging of cut streams, and protobuf's of requests that do not parse.
  setenv("GRPC_VERBOSITY", "NONE", 1);
  google::protobuf::SetLogHandler(nullptr);
  if (const char* folder = std::getenv("PATHFARM_FUZZ_WRITE_SEEDS")) {
    pathfarm::fuzz::writeRpcSeeds(folder);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pathfarm::fuzz;
  Farm farm;
  std::string_view input(reinterpret_cast<const char*>(data), size);
  // A bound on calls per input keeps one input's time in check whatever its length.
  for (int calls = 0; input.size() >= 3 && calls < 64; ++calls) {
    const auto op = static_cast<uint8_t>(input[0]);
    const size_t length =
        std::min<size_t>(static_cast<uint8_t>(input[1]) | static_cast<uint8_t>(input[2]) << 8, input.size() - 3);
    farm.calls().run(op, input.substr(3, length));
    input.remove_prefix(3 + length);
  }
  return 0;
}
