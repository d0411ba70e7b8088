#pragma once
// The dashboard's page: the files of scheduler/http/dashboard/ (HTML, script, style), embedded
// in the binary at build time by scheduler/http/dashboard/embed_assets.cmake.
#include <span>
#include <string_view>

namespace pathfarm::farm {

struct DashboardAsset {
  std::string_view path;  // as served: "/index.html", "/app.js"
  std::string_view bytes;
};

// Defined in the generated dashboard_asset_bytes.cpp.
std::span<const DashboardAsset> dashboardAssets();

// The asset served at `path` ("/" serves /index.html), or nullptr.
const DashboardAsset* findDashboardAsset(std::string_view path);
// By the file's extension: text/html, text/javascript, text/css.
std::string_view contentTypeOf(std::string_view path);

}  // namespace pathfarm::farm
