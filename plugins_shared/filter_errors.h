// The one error/refusal wrapper of every filter, for both hosts: runs a filter body and turns what it
// throws into the message the user sees ("" on success).
#pragma once

#include "filter.h"

#include <functional>
#include <string>

namespace radml {

std::string runFilter(const Filter* filter, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb,
                      const std::function<void(const std::string&)>& log,
                      const std::function<void(const std::string&)>& warning);

}  // namespace radml
