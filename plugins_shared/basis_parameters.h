// The "basis" and "degree" parameters of the filters that make radiance functions (Vanhoey et al.
// 2015, sec. 6: PB(d) in a local frame or SH(d) in the global frame), declared and read in one place.
#pragma once

#include "meshlab_host.h"

#include "radiance/basis.h"

namespace radml {

// Adds "basis" (PB / SH) and "degree" (default 4); `degreeAdvice` ends the degree's help text.
void addBasisParameters(RichParameterList& par, const QString& degreeAdvice);

// The basis the two parameters name; throws radml::Refusal for a degree the basis does not support.
rad::BasisSpec basisParameters(const RichParameterList& par);

}  // namespace radml
