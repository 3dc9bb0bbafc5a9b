// What the plugin's decorations share: their per-(view, layer) state, the fingerprint of a layer
// (what was uploaded), the tone mapping read from the parameters, messages logged once, and the
// start's GL check and refusal line.
#pragma once

#include "render/tone_mapping.h"

#include <Eigen/Core>

#include <common/interfaces.h>

#include <cstddef>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>

class GLArea;

namespace raddecorate {

// Makes the view's GL context current (the GL objects of its layers belong to it).
void makeContextCurrent(GLArea& gla);

// The state of one decoration per (view, layer): a view with a `renderer` member (std::unique_ptr).
template <class View>
class LayerViews {
public:
    LayerViews() = default;
    LayerViews(const LayerViews&) = delete;
    LayerViews& operator=(const LayerViews&) = delete;
    // GL objects cannot be released without their context here; MeshLab calls endDecorate for every
    // active decoration before closing its views. Whatever is left goes with the context.
    ~LayerViews() {
        for (auto& entry : views_) entry.second->renderer.release();
    }
    View* find(const GLArea* gla, const MeshModel& m) const {
        auto it = views_.find(Key(gla, m.id()));
        return it == views_.end() ? nullptr : it->second.get();
    }
    void erase(const GLArea* gla, const MeshModel& m) { views_.erase(Key(gla, m.id())); }
    void put(const GLArea* gla, const MeshModel& m, std::unique_ptr<View> view) {
        views_[Key(gla, m.id())] = std::move(view);
    }
    // The decoration was switched off: its GL objects are deleted in their own context.
    void end(GLArea* gla, const MeshModel& m) {
        auto it = views_.find(Key(gla, m.id()));
        if (it == views_.end()) return;
        if (gla) makeContextCurrent(*gla);
        views_.erase(it);
    }

private:
    using Key = std::pair<const GLArea*, int>;
    std::map<Key, std::unique_ptr<View>> views_;
};

// The layer's mesh as uploaded: a filter that replaced the vertex or face vector, or changed their
// counts, makes it different.
struct LayerGeometry {
    int vn = -1, fn = -1;
    const void* vertices = nullptr;
    const void* faces = nullptr;
    bool operator==(const LayerGeometry& o) const {
        return vn == o.vn && fn == o.fn && vertices == o.vertices && faces == o.faces;
    }
    bool operator!=(const LayerGeometry& o) const { return !(*this == o); }
};
LayerGeometry geometryOf(const CMeshO& mesh);

// What the uploaded buffers were made from; any change (a filter that replaced the vertex vector,
// new radiance or transfer data) triggers a new upload. startDecorate is also called again by
// MeshLab after every filter, which catches edits in place.
struct Fingerprint {
    LayerGeometry geometry;
    const void* radiance = nullptr;
    std::size_t radianceFloats = 0;
    const void* transfer = nullptr;
    std::size_t transferFloats = 0;
    bool operator==(const Fingerprint& o) const {
        return geometry == o.geometry && radiance == o.radiance && radianceFloats == o.radianceFloats &&
               transfer == o.transfer && transferFloats == o.transferFloats;
    }
    bool operator!=(const Fingerprint& o) const { return !(*this == o); }
};
Fingerprint fingerprintOf(CMeshO& mesh);

// Exposure in stops (a non-finite value counts as 0) and tone curve (0 clamp, 1 Reinhard) from the
// decoration's two parameters.
rad::ToneMapping toneMappingOf(const RichParameterList& par, const char* exposureKey, const char* toneCurveKey);

// The GL modelview pushed and multiplied by the layer's Tr (the caller pops it), as the layer's
// drawing sees it: the modelview, its inverse, and the eye in the layer's coordinates.
struct LayerEye {
    Eigen::Matrix4d modelview;
    Eigen::Matrix4d inverse;
    Eigen::Vector3d eye;
};
LayerEye enterLayerSpace(const CMeshO& mesh);

// Per-frame problems of a view, each logged once ("<decoration>: <message>"), not every frame.
class OnceLog {
public:
    explicit OnceLog(std::string decoration) : prefix_(std::move(decoration) + ": ") {}
    void report(GLLogStream& log, int level, const std::string& message);
    // A warning when `problem` (a renderer's answer, its GL errors) is not empty.
    void warnIfAny(GLLogStream& log, const std::string& problem) {
        if (!problem.empty()) report(log, GLLogStream::WARNING, problem);
    }

private:
    std::string prefix_;
    std::set<std::string> reported_;
};

// False, with a warning naming the decoration, when the GL extensions cannot be initialised.
bool glExtensionsReady(const char* decoration, MeshLabInterface& pluginLog);

// Logs "<decoration>: not started on layer '<label>': <why>" as a warning; returns false.
bool refuseStart(const char* decoration, const MeshModel& m, const std::string& why, MeshLabInterface& pluginLog);

}  // namespace raddecorate
