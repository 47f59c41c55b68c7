#pragma once

#include "camera/functions.h"

namespace anamorph {

extern const DirFunctionInfo kExpressionDirInfo;

}  // namespace anamorph
