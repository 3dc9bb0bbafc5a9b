#include "io_plugin_base.h"

#include "host_operations.h"

#include <cstdio>

namespace radml {

QList<MeshIOInterface::Format> IoPluginBase::importFormats() const {
    return {Format(format_->description(), format_->extension())};
}

QList<MeshIOInterface::Format> IoPluginBase::exportFormats() const {
    return {Format(format_->description(), format_->extension())};
}

void IoPluginBase::GetExportMaskCapability(QString& format, int& capability, int& defaultBits) const {
    capability = defaultBits = 0;
    if (format.toUpper() != format_->extension()) return;
    capability = defaultBits = format_->exportCapability();
}

bool IoPluginBase::refuse(const std::string& message) {
    errorMessage = QString::fromStdString(message);
    // The GUI shows errorMessage in a dialog, but meshlabserver's -i/-o paths drop it: say it on
    // stderr too, so batch users learn what is wrong with their file.
    std::fprintf(stderr, "%s\n", message.c_str());
    return false;
}

void IoPluginBase::logLine(const std::string& line) { Log(GLLogStream::FILTER, forThisHost(line)); }

void IoPluginBase::warningLine(const std::string& line) {
    const std::string shown = forThisHost(line);
    Log(GLLogStream::WARNING, shown);
    std::fprintf(stderr, "%s\n", shown.c_str());  // meshlabserver shows no log: batch users read stderr
}

bool IoPluginBase::open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
                        const RichParameterList&, vcg::CallBackPos* cb, QWidget*) {
    if (format.toUpper() != format_->extension())
        return refuse("This plugin only reads ." + format_->extension().toLower().toStdString() + " files.");
    FilterProgress progress(cb);
    try {
        format_->read(fileName, m, mask, progress, [this](const std::string& s) { logLine(s); },
                      [this](const std::string& s) { warningLine(s); });
        return true;
    } catch (const std::exception& e) {
        // MeshLab discards the half-built layer of a failed open; the user's other layers are untouched.
        m.cm.Clear();
        return refuse(forThisHost(e.what()));
    }
}

bool IoPluginBase::save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
                        const RichParameterList&, vcg::CallBackPos* cb, QWidget*) {
    if (format.toUpper() != format_->extension())
        return refuse("This plugin only writes ." + format_->extension().toLower().toStdString() + " files.");
    FilterProgress progress(cb);
    try {
        format_->write(fileName, m, mask, progress, [this](const std::string& s) { logLine(s); },
                       [this](const std::string& s) { warningLine(s); });
        return true;
    } catch (const std::exception& e) {
        return refuse(forThisHost(e.what()));
    }
}

}  // namespace radml
