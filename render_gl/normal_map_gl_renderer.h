// Draws a mesh with a normal map, and with LEAN mapping (Weber and Stamminger, Weber & Stamminger, Alg. 3-4),
// with OpenGL: one directional light, Blinn-Phong or the LEAN Gaussian lobe (common/bake/lean_maps.h),
// for comparing a baked normal map's appearance at every distance. No Qt, no MeshLab headers: a
// current context with GLEW initialised is all it needs. GLSL in normal_map_shaders.h.
//
// Upload once, draw many: setMesh() expands the mesh into one vertex buffer, 3 wedges per face
// (positions, vertex normals, wedge UVs; drawn un-indexed, so UV seams need no vertex splitting);
// setNormalMap()/setLeanMoments() upload RGB32F mip-mapped textures (rows flipped: images are
// stored top to bottom, GL's first row is v = 0; clamp to edge, trilinear). draw() sets uniforms
// and issues one glDrawArrays with the current fixed-function matrices, depth test GL_LEQUAL and a
// polygon offset of (-1, -1) (as radiance_gl_renderer.h), and restores every binding and state it
// touches.
//
// Needs shaders (GL 3.2, GLSL 1.50, compatibility profile: gl_capabilities.h); otherwise every
// set*/draw call returns the reason and draws nothing (there is no fixed-function fallback).
#pragma once

#include "gl_capabilities.h"
#include "irradiance_grid_textures.h"
#include "normal_map_shaders.h"
#include "radiance_gl_renderer.h"  // GlRendererError

#include "bake/lean_maps.h"
#include "bake/normal_baker.h"  // TangentFrame
#include "image/rgb_image.h"
#include "lod/pop_buffer.h"
#include "lod/texcoord_correction.h"
#include "render/tone_mapping.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace radgl {

// One directional light in object space. Linear colour = ambient * albedo
//   + lightColor * (albedo * max(n.L, 0) + specular * spec), spec = (H.n)^s (Blinn-Phong) or the
// LEAN lobe (leanSpecular), 0 where n.L <= 0.
struct NormalMapLighting {
    Eigen::Vector3d lightDirection{0.0, 0.0, 1.0};  // toward the light (normalised by draw)
    Eigen::Vector3d lightColor{1.0, 1.0, 1.0};
    Eigen::Vector3d albedo{0.5, 0.5, 0.5};
    Eigen::Vector3d specular{0.5, 0.5, 0.5};
    double shininess = 50.0;
    Eigen::Vector3d ambient{0.0, 0.0, 0.0};
    // Indirect light from the grid set by setIrradianceGrid (ignored, with draw() saying so, when
    // there is none).
    IndirectLight indirect = IndirectLight::None;
    // The grid's directional weights (lighting/irradiance_vector_grid.h): the paper's n_a^2 or |n_a|.
    bool gridAbsoluteWeights = false;
};

class NormalMapGlRenderer {
public:
    // The context must be current. A compile/link failure or missing GL feature is reported by
    // shaderProblem() (and by every later call), not thrown.
    explicit NormalMapGlRenderer(const GlCapabilities& caps);
    // Releases the GL objects: the context that created them must be current.
    ~NormalMapGlRenderer();
    NormalMapGlRenderer(const NormalMapGlRenderer&) = delete;
    NormalMapGlRenderer& operator=(const NormalMapGlRenderer&) = delete;

    const std::string& shaderProblem() const { return shaderProblem_; }

    // positions, normals: 3 floats per vertex; faces: 3 indices per face; wedgeUv: 6 floats per
    // face (texture_atlas.h). Throws GlRendererError on inconsistent input. Returns why it cannot
    // draw (no shaders), else empty.
    std::string setMesh(const float* positions, const float* normals, std::size_t vertexCount, const std::uint32_t* faces,
                        std::size_t faceCount, const float* wedgeUv);
    // The same mesh as a POP buffer (Limper et al. 2013, lod/pop_buffer.h, built from these positions
    // and faces): the corners are uploaded in the buffer's triangle order with each vertex's level-16
    // cell and, when `correction` is given (computed from `wedgeUv`), its corner's d(uv)/d(xyz), so that
    // the vertex shader snaps positions to the grid of a level and corrects the texture coordinates
    // (Weber & Stamminger, Alg. 1) and a level is drawn as a prefix of the buffer. Throws
    // GlRendererError when `pop` does not match the mesh.
    std::string setPopMesh(const float* positions, const float* normals, std::size_t vertexCount,
                           const std::uint32_t* faces, std::size_t faceCount, const float* wedgeUv,
                           const rad::PopBuffer& pop, const rad::TexCoordDerivatives* correction);
    // The level the next draw() shows: 0 = the mesh as uploaded (no snapping), 1..16 a POP level
    // (needs setPopMesh); `correct` applies Alg. 1 (needs the derivatives). Returns the reason when it
    // cannot be drawn, else empty.
    std::string setPopLevel(int level, bool correct);
    int popLevel() const { return popLevel_; }
    // Triangles the next draw() issues.
    std::size_t drawnFaceCount() const;
    bool hasPopBuffer() const { return !popLevelEnd_.empty(); }

    // Levels 0..K of the map (buildNormalPyramid, or any chain w >> k x h >> k down to 1 x 1, 3
    // channels). Object-space unit normals, or tangent-space ones (normal_baker.h) when
    // tangentSpace, decoded in `frame`: MikkTSpace (Mikkelsen 2008: the mesh's per-corner tangents,
    // computed by setMesh, interpolated, B = sign N x T, n = normalize(x T + y B + z N)) or the
    // per-face dP/du frame (maps baked before MikkTSpace; bake descriptions without a
    // tangent_frame line). Drops previously set LEAN moments. Returns the reason on refusal, else empty.
    std::string setNormalMap(const std::vector<rad::MipImage>& pyramid, bool tangentSpace,
                             rad::TangentFrame frame = rad::TangentFrame::PerFaceUvDerivative);
    // LEAN moments, MIP levels 1..K of the current normal map (LeanMaps::moments or
    // readLeanMoments). Refused (reason returned) for a tangent-space map: LEAN filters
    // object-space normals (Weber and Stamminger sec. 3.2-3.3), or when the sizes do not match the map.
    std::string setLeanMoments(const std::vector<rad::MipImage>& levels1toK);
    bool hasNormalMap() const { return normalTexture_ != 0; }

    // Per-vertex albedo rho (linear RGB, 3 floats per vertex of the mesh given to setMesh /
    // setPopMesh), used instead of lighting.albedo until the next mesh. Returns the reason on
    // refusal (no mesh, count mismatch, no shaders), else empty.
    std::string setVertexColors(const float* rgb, std::size_t vertexCount);
    bool hasVertexColors() const { return colorBuffer_ != 0; }

    // A diffuse map (8-bit sRGB, rows top to bottom, read with the mesh's wedge UVs: the bake's
    // B_diffuse.png) as rho, before the vertex colours and the albedo uniform; decoded to linear by
    // GL (GL_SRGB8), mip-mapped, on texture unit 2. Kept until replaced. Returns the reason on
    // refusal, else empty.
    std::string setDiffuseMap(const rad::Image8& image);
    bool hasDiffuseMap() const { return diffuseTexture_ != 0; }

    // The irradiance vector grid of the scene (Granier et al. 2007), in the mesh's object
    // coordinates, uploaded as 12 RGB16F 3D textures (irradiance_grid_textures.h) on texture units
    // 3..14 (15 units in all with the normal map, the LEAN moments and the diffuse map). Returns the reason on refusal (GL limits, shaders), else empty; `note` as
    // IrradianceGridTextures::upload. Kept across setMesh calls.
    std::string setIrradianceGrid(const rad::IrradianceVectorGrid& grid, std::string& note);
    void clearIrradianceGrid() { grid_.release(); }
    bool hasIrradianceGrid() const { return grid_.ready(); }
    std::size_t irradianceGridBytes() const { return grid_.gpuBytes(); }
    bool hasLeanMoments() const { return momentTexture_ != 0; }

    // Draws the mesh; eyeObject: the eye in the mesh's object coordinates. Returns why nothing was
    // drawn (no mesh, no map for the map modes, no moments or a tangent-space map for Lean, no
    // shaders), else empty.
    std::string draw(NormalMapShading mode, const NormalMapLighting& lighting, const rad::ToneMapping& toneMapping,
                     const Eigen::Vector3d& eyeObject);

    // Hides what is already drawn of this mesh at its full resolution (MeshLab's own rendering of
    // the layer, under a decoration that draws a coarser level): where the uploaded mesh, unsnapped,
    // is the visible surface (depth test GL_LEQUAL with the draw's polygon offset), the colour becomes
    // the vertical gradient from `bottom` (row 0) to `top` (the last row) of the current viewport, as
    // MeshLab paints its background, and the depth is reset to the far plane so that the level drawn
    // next is not hidden by the surface it replaces. Those pixels are marked in the stencil buffer;
    // without stencil bits the depth is reset over the whole projection of the mesh (other layers in
    // front of it then lose their depth there). Restores every state it touches.
    std::string eraseFullMesh(const Eigen::Vector3f& top, const Eigen::Vector3f& bottom);

    // GL errors seen since the last call, or empty.
    std::string takeGlErrors();

private:
    void buildProgram();
    void checkGl(const char* where);
    void uploadCorners(const std::vector<float>& corners, int floatsPerCorner);
    unsigned uploadPyramid(const std::vector<rad::MipImage>& levels);

    GlCapabilities caps_;
    std::string shaderProblem_, errors_;
    unsigned program_ = 0;
    unsigned eraseProgram_ = 0;
    int eraseTop_ = -1, eraseBottom_ = -1, eraseHeight_ = -1, eraseDepth_ = -1;
    struct Uniforms {
        int normalMap = -1, moments = -1, mode = -1, tangentSpace = -1, mikkTSpace = -1, textureSize = -1, eye = -1,
            lightDirection = -1, lightColor = -1, albedo = -1, specular = -1, ambient = -1, shininess = -1,
            exposureScale = -1, toneCurve = -1, popLevel = -1, popCorrection = -1, boxMin = -1, boxExtent = -1,
            indirect = -1, vertexAlbedo = -1, diffuseMap = -1, useDiffuseMap = -1, gridOrigin = -1, gridCellSize = -1, gridVertexCounts = -1,
            gridAbsoluteWeights = -1;
        int gridSamplers[IrradianceGridTextures::kTextures] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
    } u_;
    // The mesh's vertex of every uploaded corner (for setVertexColors), in upload order.
    std::vector<std::uint32_t> cornerVertex_;
    std::size_t meshVertexCount_ = 0;
    unsigned colorBuffer_ = 0;
    unsigned diffuseTexture_ = 0;
    IrradianceGridTextures grid_;
    unsigned vertexBuffer_ = 0;
    std::size_t cornerCount_ = 0;
    int floatsPerCorner_ = 12;  // set by uploadCorners
    // POP buffer: triangles drawn per level (index = level), box, whether derivatives were uploaded.
    std::vector<std::size_t> popLevelEnd_;
    Eigen::Vector3f boxMin_ = Eigen::Vector3f::Zero(), boxExtent_ = Eigen::Vector3f::Zero();
    bool popDerivatives_ = false;
    int popLevel_ = 0;
    bool popCorrect_ = false;
    unsigned normalTexture_ = 0, momentTexture_ = 0;
    int mapWidth_ = 0, mapHeight_ = 0, mapLevels_ = 0;
    bool tangentSpace_ = false;
    bool mikkTSpace_ = false;
};

}  // namespace radgl
