#include "output_naming.h"

#include <QDir>
#include <QFileInfo>

namespace radml {

QString outputBaseFromParameter(const QString& given, const QString& label) {
    QString base = given.trimmed();
    if (base.isEmpty()) return {};
    if (QFileInfo(base).isDir()) return QDir(QFileInfo(base).absoluteFilePath()).filePath(label);
    if (base.endsWith(".png", Qt::CaseInsensitive)) base.chop(4);
    if (base.endsWith("_normal")) base.chop(7);
    return QFileInfo(base).absoluteFilePath();
}

}  // namespace radml
