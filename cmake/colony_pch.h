// Precompiled for libcolony, the plugins built here and the test programs
// (COLONY_PCH, CMakeLists.txt): the standard, Eigen and core headers nearly
// every source includes, parsed once per target instead of once per source.
// Sources still include what they use; a build with COLONY_PCH=OFF (or through
// ccache, see CMakeLists.txt) checks that they do.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/device.h"
#include "core/error.h"
#include "core/log.h"
#include "core/registry.h"
#include "core/simulation.h"
