// Building SplatRenderer's GL programs from renderer/shaders/: the variant #defines of the splat and tile
// programs (built on first use), the fixed programs, and the driver's loop-limit probe.
#include "splat_renderer_state.h"
#include "gl/shader_sources.h"
#include "renderer/oracle/near_layer.h"

#include <string>
#include <utility>

namespace renderer {

namespace {

// The #define of the programs that share the opaque-tile size.
std::string opaqueTileDefine() { return "#define OPAQUE_TILE " + std::to_string(kOpaqueTilePx) + "\n"; }

// The #defines of a variant's features. Every set the renderer builds is listed in
// renderer/shaders/programs.cmake (validated at build time); programSource() refuses any other.
std::string variantDefines(int bits) {
    const std::pair<int, const char*> defines[] = {{kCounters, "COUNTERS"}, {kSurface, "SURFACE"},
                                                   {kSplatShading, "SPLAT_SHADING"},
                                                   {kFragmentShading, "FRAGMENT_SHADING"}, {kHeatmap, "HEATMAP"},
                                                   {kAdaptive, "ADAPTIVE"}, {kOcclusion, "OCCLUSION"},
                                                   {kGradientOpacity, "GRADIENT_OPACITY"}, {kTf2d, "TF_2D"}};
    std::string header;
    for (auto [bit, name] : defines)
        if (bits & bit) header += std::string("#define ") + name + "\n";
    return header;
}

} // namespace

GLuint SplatRenderer::Gl::splatProgram(int bits) {
    auto it = splatPrograms.find(bits);
    if (it != splatPrograms.end()) return it->second;
    const std::string defines = opaqueTileDefine() + variantDefines(bits);
    const GLuint p = gl::buildProgram("splat", programSource("splat", defines, "splat.vert").c_str(),
                                      programSource("splat", defines, "splat.frag").c_str());
    splatPrograms[bits] = p;
    return p;
}

GLuint SplatRenderer::Gl::tileProgram(int pass, int bits) {
    const int key = pass | bits;
    auto it = tilePrograms.find(key);
    if (it != tilePrograms.end()) return it->second;
    std::string defines = opaqueTileDefine() + variantDefines(bits);
    if (bits & kTileXRay) defines += "#define XRAY\n";
    if (bits & kTileColumnRecurrence) defines += "#define COLUMN_RECURRENCE\n";
    defines += "#define SPLAT_TILE " + std::to_string(kSplatTilePx) + "\n#define BUSY_ROW 4096u\n";
    defines += "#define RECORD_VEC4S " + std::to_string(recordVec4s(bits)) + "u\n";
    defines += "#define ENTRY_TEXELS " + std::to_string(entryTexels(bits)) + "u\n";
    if (pass == kTileSplat) defines += "#define RUN_LANES " + std::to_string(driver.runLanes) + "\n";
    const char* program = pass == kTileSplat     ? "tile_record"
                          : pass == kTileOffsets ? "tile_offsets"
                          : pass == kTileBases   ? "tile_bases"
                          : pass == kTileScatter ? "tile_scatter"
                          : bits & kTileCompositePixels ? "tile_composite_pixels"
                                                 : "tile_composite";
    const std::string source = programSource(program, defines, std::string(program) + ".comp");
    const GLuint p = gl::buildComputeProgram("tiled_splatting", source.c_str());
    tilePrograms[key] = p;
    return p;
}

void SplatRenderer::Gl::buildFixedPrograms() {
    // A full-screen pass: the one triangle of fullscreen.vert, then `fragment`.
    auto fullscreen = [](const char* program, const std::string& defines, const char* fragment) {
        return gl::buildProgram(program, programSource(program, defines, "fullscreen.vert").c_str(),
                                programSource(program, defines, fragment).c_str());
    };
    // A compute pass: <program>.comp.
    auto compute = [](const char* program, const std::string& defines) {
        return gl::buildComputeProgram(program,
                                       programSource(program, defines, std::string(program) + ".comp").c_str());
    };
    for (int heat = 0; heat < 2; ++heat)
        compositePrograms[size_t(heat)] =
            fullscreen("sheet_composite", heat ? "#define HEATMAP\n" : "", "sheet_composite.frag");
    opaqueMaskProgram = fullscreen("opaque_mask", "", "opaque_mask.frag");
    resolveProgram = fullscreen("xray_resolve", "", "xray_resolve.frag");
    displayProgram = fullscreen("display", "", "display.frag");
    commandsProgram = compute("bucket_commands", "");
    patchProgram = compute("patch_modes", "");
    opaqueTilesProgram = compute("opaque_tiles", opaqueTileDefine());
    const std::string nearDefines = "#define MAX_NEAR_KERNELS " + std::to_string(kMaxNearKernels) + "u\n";
    nearKernelsProgram = compute("near_kernels", nearDefines);
    nearLayerProgram = fullscreen("near_layer", nearDefines, "near_layer.frag");
}

// How many iterations the driver lets one invocation's loops run: a loop of 2^20 iterations counts
// them. llvmpipe stops it at 65535 (its LP_MAX_TGSI_LOOP_ITERATIONS, shared by every loop of the
// shader), and then silently ends every later loop after one iteration. 0: it ran to the end.
uint32_t measureLoopLimit() {
    constexpr GLuint kTrip = 1u << 20;
    const GLuint program =
        gl::buildComputeProgram("loop_limit", programSource("loop_limit", "", "loop_limit.comp").c_str());
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, 4, nullptr, 0);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "uN"), kTrip);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint iterations = 0;
    glGetNamedBufferSubData(buffer, 0, 4, &iterations);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glUseProgram(0);
    glDeleteBuffers(1, &buffer);
    glDeleteProgram(program);
    return iterations < kTrip ? iterations : 0;
}

} // namespace renderer
