// Where a filter that writes maps puts them: the one rule for the "outputFile" parameter of the
// normal-map bake and the out-of-core simplification, whose files are <base>_normal.png and its
// companions.
#pragma once

#include <QString>

namespace radml {

// The output base the "outputFile" parameter names: an existing folder receives files named `label`
// in it; a path has ".png" and a trailing "_normal" dropped (so the normal map's own name works). Empty
// when the parameter is empty: the filter's default place applies.
QString outputBaseFromParameter(const QString& given, const QString& label);

}  // namespace radml
