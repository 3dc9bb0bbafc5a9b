// radiance_filter_script: writes a MeshLab 2020.09 filter script (.mlx) whose parameter lists come
// from the filters themselves. meshlabserver 2020.09 refuses a script that omits a parameter, so
// scripts written by hand re-type every filter's full list and drift when a filter gains one; this
// program asks each plugin for its parameters (as MeshLab's GUI does), writes all of them with
// MeshLab's own XML writer, and changes only the values named on the command line.
//
//   radiance_filter_script --plugins DIR [--layers N] --out OUT.mlx
//       --filter "FILTER NAME" [name=value]... [--filter "OTHER" [name=value]...]...
// --out - writes to standard output; --elements-only writes the <filter> elements alone, for
// scripts that assemble a longer script from pieces.
//
// Values: numbers, true/false, an enum's index or label, "x,y,z" for points, "r,g,b[,a]" for
// colours, a layer index for meshes. Defaults that depend on the document are computed on N layers
// (default 1) holding a unit cube: sizes relative to the bounding box come out relative to a
// diagonal of sqrt(3), so a script that needs a particular size names it. An unknown filter or
// parameter, or a value of the wrong kind, is refused with the names that exist; nothing is written.
#include <common/filterscript.h>
#include <common/interfaces.h>
#include <common/meshmodel.h>
#include <vcg/complex/algorithms/create/platonic.h>
#include <vcg/complex/algorithms/update/bounding.h>

#include <QApplication>
#include <QDir>
#include <QDomDocument>
#include <QPluginLoader>
#include <QSaveFile>
#include <QTextStream>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct FilterRequest {
    QString name;
    std::vector<std::pair<QString, QString>> values;  // name=value, in command-line order
};

struct Request {
    QString pluginDir;
    QString output;
    int layers = 1;
    bool elementsOnly = false;
    std::vector<FilterRequest> filters;
};

const char* kUsage =
    "usage: radiance_filter_script --plugins DIR [--layers N] [--elements-only] --out OUT.mlx|-\n"
    "         --filter \"FILTER NAME\" [name=value]... [--filter \"OTHER\" [name=value]...]...\n";

[[noreturn]] void refuse(const QString& message) { throw std::runtime_error(message.toStdString()); }

Request parseCommandLine(const QStringList& args) {
    Request request;
    for (int i = 1; i < args.size(); ++i) {
        const QString& arg = args[i];
        const bool hasNext = i + 1 < args.size();
        if (arg == "--plugins" && hasNext) request.pluginDir = args[++i];
        else if (arg == "--out" && hasNext) request.output = args[++i];
        else if (arg == "--elements-only") request.elementsOnly = true;
        else if (arg == "--layers" && hasNext) request.layers = args[++i].toInt();
        else if (arg == "--filter" && hasNext) request.filters.push_back({args[++i], {}});
        else if (!request.filters.empty() && arg.contains('=') && !arg.startsWith("--")) {
            const int eq = arg.indexOf('=');
            request.filters.back().values.emplace_back(arg.left(eq), arg.mid(eq + 1));
        } else refuse(QString("unexpected argument '%1'").arg(arg));
    }
    if (request.pluginDir.isEmpty() || request.output.isEmpty() || request.filters.empty())
        refuse("--plugins, --out and at least one --filter are required");
    if (request.layers < 1) refuse("--layers takes a positive number");
    return request;
}

// Every filter plugin of the folder, loaded as MeshLab's plugin manager does. A library that is not
// a filter plugin (io, decorate, render) or does not load is skipped.
std::vector<MeshFilterInterface*> loadFilterPlugins(const QString& folder) {
    const QDir dir(folder);
    if (!dir.exists()) refuse(QString("plugin folder '%1' does not exist").arg(folder));
    std::vector<MeshFilterInterface*> plugins;
    for (const QString& file : dir.entryList(QStringList{"*.so"}, QDir::Files, QDir::Name)) {
        QPluginLoader loader(dir.absoluteFilePath(file));
        if (auto* filter = qobject_cast<MeshFilterInterface*>(loader.instance())) plugins.push_back(filter);
    }
    if (plugins.empty()) refuse(QString("no MeshLab filter plugin in '%1'").arg(folder));
    return plugins;
}

// The layers the defaults are computed on: unit cubes, the first one current.
void addLayers(MeshDocument& document, int count) {
    for (int i = 0; i < count; ++i) {
        MeshModel* cube = document.addNewMesh("", QString("cube %1").arg(i));
        vcg::tri::Hexahedron(cube->cm);
        vcg::tri::UpdateBounding<CMeshO>::Box(cube->cm);
    }
    document.setCurrentMesh(0);
}

RichParameterList declaredParameters(const std::vector<MeshFilterInterface*>& plugins, const QString& filterName,
                                     MeshDocument& document) {
    QStringList similar;
    for (MeshFilterInterface* plugin : plugins)
        for (QAction* action : plugin->actions()) {
            if (action->text() == filterName) {
                RichParameterList parameters;
                plugin->initParameterSet(action, document, parameters);
                return parameters;
            }
            if (action->text().section(':', 0, 0) == filterName.section(':', 0, 0)) similar << action->text();
        }
    refuse(QString("no filter named '%1'%2").arg(filterName,
        similar.isEmpty() ? QString() : QString("; filters of that group: ") + similar.join(", ")));
}

// The Param element named `name` in the filter element, with the names that exist for the refusal.
QDomElement parameterElement(const QDomElement& filter, const QString& name) {
    QStringList names;
    for (QDomElement p = filter.firstChildElement("Param"); !p.isNull(); p = p.nextSiblingElement("Param")) {
        if (p.attribute("name") == name) return p;
        names << p.attribute("name");
    }
    refuse(QString("filter '%1' has no parameter '%2'; its parameters: %3")
               .arg(filter.attribute("name"), name, names.join(", ")));
}

// The comma-separated numbers of `value`, trimmed.
QStringList numbers(const QString& value, int minCount, int maxCount, const QString& what) {
    QStringList parts = value.split(',');
    bool ok = parts.size() >= minCount && parts.size() <= maxCount;
    for (int i = 0; ok && i < parts.size(); ++i) {
        parts[i] = parts[i].trimmed();
        parts[i].toDouble(&ok);
    }
    if (!ok) refuse(QString("'%1' is not %2").arg(value, what));
    return parts;
}

// Writes `value` into the element the way MeshLab 2020.09's RichParameter XML reader expects.
void setValue(QDomElement& param, const QString& value) {
    const QString type = param.attribute("type");
    const auto refuseValue = [&](const char* expected) {
        refuse(QString("parameter '%1' (%2) takes %3, not '%4'").arg(param.attribute("name"), type, expected, value));
    };
    bool ok = true;
    if (type == "RichBool") {
        if (value != "true" && value != "false" && value != "1" && value != "0") refuseValue("true or false");
        param.setAttribute("value", (value == "true" || value == "1") ? "true" : "false");
    } else if (type == "RichInt" || type == "RichMesh") {
        const int v = value.toInt(&ok);
        if (!ok || (type == "RichMesh" && v < 0)) refuseValue(type == "RichMesh" ? "a layer index" : "an integer");
        param.setAttribute("value", value);
    } else if (type == "RichFloat" || type == "RichAbsPerc" || type == "RichDynamicFloat") {
        value.toDouble(&ok);
        if (!ok) refuseValue("a number");
        param.setAttribute("value", value);
    } else if (type == "RichEnum") {
        const int count = param.attribute("enum_cardinality").toInt();
        int index = value.toInt(&ok);
        if (!ok)
            for (index = 0; index < count && param.attribute(QString("enum_val%1").arg(index)) != value; ++index) {}
        if (index < 0 || index >= count) refuseValue("one of its labels or their index");
        param.setAttribute("value", QString::number(index));
    } else if (type == "RichString" || type == "RichOpenFile" || type == "RichSaveFile") {
        param.setAttribute("value", value);
    } else if (type == "RichPoint3f" || type == "RichDirection") {
        const QStringList xyz = numbers(value, 3, 3, "three numbers 'x,y,z'");
        param.setAttribute("x", xyz[0]);
        param.setAttribute("y", xyz[1]);
        param.setAttribute("z", xyz[2]);
    } else if (type == "RichColor") {
        const QStringList rgba = numbers(value, 3, 4, "a colour 'r,g,b' or 'r,g,b,a' (0..255)");
        const char* channels[] = {"r", "g", "b", "a"};
        for (int c = 0; c < rgba.size(); ++c) param.setAttribute(channels[c], rgba[c]);
    } else {
        refuseValue("no value from the command line (unsupported type)");
    }
}

QDomDocument scriptDocument(const Request& request, const std::vector<MeshFilterInterface*>& plugins,
                            MeshDocument& document) {
    FilterScript script;
    for (const FilterRequest& filter : request.filters) {
        FilterNameParameterValuesPair entry;
        entry.first = filter.name;
        entry.second = declaredParameters(plugins, filter.name, document);
        script.append(entry);
    }
    QDomDocument xml = script.xmlDoc();
    QDomElement filterElement = xml.documentElement().firstChildElement("filter");
    for (const FilterRequest& filter : request.filters) {
        for (const auto& [name, value] : filter.values) {
            QDomElement param = parameterElement(filterElement, name);
            setValue(param, value);
        }
        filterElement = filterElement.nextSiblingElement("filter");
    }
    return xml;
}

QString scriptText(const QDomDocument& xml, bool elementsOnly) {
    if (!elementsOnly) return xml.toString(1);
    QString text;
    QTextStream stream(&text);
    for (QDomElement f = xml.documentElement().firstChildElement("filter"); !f.isNull(); f = f.nextSiblingElement("filter"))
        f.save(stream, 1);
    return text;
}

// Written to a temporary file and renamed: a refused or failed write leaves no half script.
void writeAtomically(const QString& text, const QString& path) {
    if (path == "-") {
        std::fputs(text.toUtf8().constData(), stdout);
        if (std::fflush(stdout) != 0) refuse("cannot write to standard output");
        return;
    }
    QSaveFile file(path);
    if (!file.open(QIODevice::WriteOnly)) refuse(QString("cannot write '%1': %2").arg(path, file.errorString()));
    const QByteArray bytes = text.toUtf8();
    if (file.write(bytes) != bytes.size()) refuse(QString("cannot write '%1': %2").arg(path, file.errorString()));
    if (!file.commit()) refuse(QString("cannot write '%1': %2").arg(path, file.errorString()));
}

}  // namespace

int main(int argc, char** argv) {
    // Plugins create QActions (Qt Widgets): a QApplication on the offscreen platform, no display.
    qputenv("QT_QPA_PLATFORM", "offscreen");
    QApplication app(argc, argv);
    try {
        const Request request = parseCommandLine(app.arguments());
        const std::vector<MeshFilterInterface*> plugins = loadFilterPlugins(request.pluginDir);
        MeshDocument document;
        addLayers(document, request.layers);
        writeAtomically(scriptText(scriptDocument(request, plugins, document), request.elementsOnly), request.output);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "radiance_filter_script: %s\n%s", error.what(), kUsage);
        return 2;
    }
    return 0;
}
