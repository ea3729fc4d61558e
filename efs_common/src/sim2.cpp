// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/sim2.h"

#include <sstream>

namespace efs {

std::string Sim2::toString() const {
  std::ostringstream os;
  os << "Sim2{yaw_rad=" << yaw_rad << ", scale=" << scale << ", t_m=(" << t_m.x() << ", " << t_m.y()
     << ")" << (reflected ? ", reflected" : "") << "}";
  return os.str();
}

}  // namespace efs
