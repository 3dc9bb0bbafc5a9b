// The error every bake step throws for an input it must refuse (the message says what is wrong and
// how to fix it): an InputError of the error contract (errors/error_categories.h).
#pragma once

#include "errors/error_categories.h"

namespace rad {

struct BakeInputError : InputError {
    using InputError::InputError;
};

}  // namespace rad
