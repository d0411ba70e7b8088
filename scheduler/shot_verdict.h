#pragma once
// The verdict of a shot's report: whether its pipeline paid off against plain pt at equal
// error, claiming only what the figures' 95 % intervals support ("paid off", "did not pay
// off", or that the reference cannot tell), and the interval figures it rests on.
#include <map>
#include <optional>
#include <string>

#include "pathfarm/report.pb.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// The evaluation's figure NAME.SUFFIX with its interval (NAME_low.SUFFIX, NAME_high.SUFFIX;
// an end not given is unbounded), or nothing when the figure is not there.
std::optional<Interval> intervalFigure(const std::map<std::string, double>& figures, const std::string& name,
                                       const std::string& suffix = "");

// "0.0123 (0.0101 to 0.0145)", with `pattern` for each number.
std::string intervalText(const Interval& interval, const char* pattern);

// Sets the report's cost at equal error, its interval and the verdict from the evaluation's
// figures (TaskRecord metrics of the evaluate task) and the report's relative cost.
void judge(ShotReport& report, Pipeline pipeline, const std::map<std::string, double>& figures);

}  // namespace pathfarm::farm
