#include "io_plugin_base.h"

#include "host_operations.h"

namespace radml {

std::list<FileFormat> IoPluginBase::importFormats() const {
    return {FileFormat(format_->description(), format_->extension())};
}

std::list<FileFormat> IoPluginBase::exportFormats() const {
    return {FileFormat(format_->description(), format_->extension())};
}

void IoPluginBase::exportMaskCapability(const QString& format, int& capability, int& defaultBits) const {
    capability = defaultBits = 0;
    if (format.toUpper() != format_->extension()) return;
    capability = defaultBits = format_->exportCapability();
}

void IoPluginBase::logLine(const std::string& line) { log(GLLogStream::FILTER, forThisHost(line)); }

void IoPluginBase::warningLine(const std::string& line) { log(GLLogStream::WARNING, forThisHost(line)); }

void IoPluginBase::open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
                        const RichParameterList&, vcg::CallBackPos* cb) {
    if (format.toUpper() != format_->extension())
        throw MLException("This plugin only reads ." + format_->extension().toLower() + " files.");
    FilterProgress progress(cb);
    try {
        format_->read(fileName, m, mask, progress, [this](const std::string& s) { logLine(s); },
                      [this](const std::string& s) { warningLine(s); });
    } catch (const MLException&) {
        m.cm.Clear();
        throw;
    } catch (const std::exception& e) {
        // The host discards the layer of a failed open; the user's other layers are untouched.
        m.cm.Clear();
        throw MLException(QString::fromStdString(forThisHost(e.what())));
    }
}

void IoPluginBase::save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
                        const RichParameterList&, vcg::CallBackPos* cb) {
    if (format.toUpper() != format_->extension())
        throw MLException("This plugin only writes ." + format_->extension().toLower() + " files.");
    FilterProgress progress(cb);
    try {
        format_->write(fileName, m, mask, progress, [this](const std::string& s) { logLine(s); },
                       [this](const std::string& s) { warningLine(s); });
    } catch (const MLException&) {
        throw;
    } catch (const std::exception& e) {
        throw MLException(QString::fromStdString(forThisHost(e.what())));
    }
}

}  // namespace radml
