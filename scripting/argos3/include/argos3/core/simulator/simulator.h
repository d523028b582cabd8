// ARGoS compatibility layer (Colony): ARGoS's simulator header. Colony's
// layer gives loop functions the space (CLoopFunctions::GetSpace); the
// simulator object itself (CSimulator, GetSimulator()) is not provided.
#pragma once

#include "argos3/core/simulator/loop_functions.h"
#include "argos3/core/simulator/space/space.h"
