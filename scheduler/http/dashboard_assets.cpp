#include "scheduler/http/dashboard_assets.h"

namespace pathfarm::farm {

const DashboardAsset* findDashboardAsset(std::string_view path) {
  if (path == "/") path = "/index.html";
  for (const DashboardAsset& asset : dashboardAssets())
    if (asset.path == path) return &asset;
  return nullptr;
}

std::string_view contentTypeOf(std::string_view path) {
  if (path.ends_with(".html")) return "text/html; charset=utf-8";
  if (path.ends_with(".js")) return "text/javascript; charset=utf-8";
  if (path.ends_with(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

}  // namespace pathfarm::farm
