// The heavy third-party and standard headers most fuzzed sources include, precompiled once
// (with their templates instantiated) by bench/fuzz.sh: a third of the compile time.
#pragma once
#include <spdlog/spdlog.h>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>
