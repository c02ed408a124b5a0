// The settings, viewport, stats and help panels and the error modal. They edit EditorState and show
// what the app hands them; they never call GL or touch renderer objects beyond reading their stats.
#include "ui/panels.h"

#include "renderer/errors.h"
#include "renderer/model/transfer_function.h"
#include "renderer/oracle/demo_scenes.h"
#include "ui/file_browser.h"
#include "ui/footprint_inspector.h"
#include "ui/session.h"
#include "slab_section.h"
#include "split_viewport.h"
#include "widgets.h"

#include <imgui.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>

namespace ui {

namespace {

// The axis names renderer::axisFromName() understands; an up vector that is none of them (set
// programmatically) shows as "custom" until one is picked.
bool drawUpAxisCombo(glm::dvec3& up) {
    static const std::array<const char*, 6> kAxes{"z", "-z", "y", "-y", "x", "-x"};
    const char* current = "custom";
    for (const char* axis : kAxes)
        if (renderer::axisFromName(axis) == up) current = axis;
    bool changed = false;
    if (ImGui::BeginCombo("Up axis", current)) {
        for (const char* axis : kAxes) {
            const bool selected = axis == current;
            if (ImGui::Selectable(axis, selected) && !selected)
                up = renderer::axisFromName(axis), changed = true;
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

} // namespace

const char* dropFile(EditorState& state, const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".xml") { // 3D Slicer's volume-rendering presets: the TF loader imports the first
        state.tfFile = file.string();
        state.pendingFile = FileAction::LoadTransferFunction;
        return "Transfer function";
    }
    if (ext != ".json") {
        state.volumeFile = file.string();
        state.pendingFile = FileAction::OpenVolume;
        return "Settings";
    }
    // A JSON that does not parse goes to the TF loader, whose error names the file and the fault; so does
    // anything that is not a regular file (a FIFO would block the window here).
    std::error_code ec;
    std::ifstream in;
    if (std::filesystem::is_regular_file(file, ec)) in.open(file);
    const nlohmann::json j = in.is_open() ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json();
    if (j.is_object() && j.contains("splatlab_session")) {
        state.sessionFile = file.string();
        state.pendingFile = FileAction::OpenSession;
        return "Settings";
    }
    state.tfFile = file.string();
    state.pendingFile = FileAction::LoadTransferFunction;
    return "Transfer function";
}

SettingsChanges drawSettingsPanel(EditorState& state) {
    SettingsChanges changes;
    renderer::SplatSettings& s = state.settings;
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 7.0f); // leaves room for the labels on the right

    sectionTitle("Files");
    // A volume picked in the browser opens at once: opening it is all that field is for.
    if (pathField(
            "Volume", state.volumeFile, FileKind::Volume, state,
            "A volume file: .nrrd/.nhdr, .mhd/.mha, .nii(.gz), .slc, .dat, .tif, .raw (dims and type in the "
            "name),\nor a folder of slices"))
        changes.openVolume = true;
    if (ImGui::Button("Open volume") || takePendingFile(state, FileAction::OpenVolume)) changes.openVolume = true;
    const std::optional<std::string> shownScene = renderer::demoSceneOfPath(state.loadedVolume);
    if (ImGui::BeginCombo("Demo scene", shownScene ? shownScene->c_str() : "(pick one)", ImGuiComboFlags_HeightLarge)) {
        for (const renderer::DemoSceneInfo& scene : renderer::demoSceneList()) {
            if (ImGui::Selectable(scene.name.c_str(), scene.name == shownScene)) changes.openScene = scene.name;
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", scene.lookFor.c_str());
        }
        ImGui::EndCombo();
    }
    hint("Scenes that show when each filter wins (the hard cases and 000 fig. 8's board), each in its own TF\n"
         "and view; also `splatlab editor --scene NAME`");
    if (shownScene)
        for (const renderer::DemoSceneInfo& scene : renderer::demoSceneList())
            if (scene.name == *shownScene) textWrapped("Look for: %s", scene.lookFor.c_str());
    pathField("Session", state.sessionFile, FileKind::Session, state,
              "A session (JSON): the volume's path, transfer function, window, camera and every setting");
    if (ImGui::Button("Open session") || takePendingFile(state, FileAction::OpenSession)) {
        try {
            changes.sessionVolume = loadSession(state.sessionFile, state);
            noteRecentFile(state, FileKind::Session, state.sessionFile);
            changes.sessionOpened = changes.settingsChanged = changes.cameraChanged = true;
        } catch (const renderer::LoadError& e) {
            state.errorMessage = e.what();
        }
    }
    ImGui::SameLine();
    if (ImGui::Button("Save session")) {
        try {
            saveSession(state, state.loadedVolume, state.sessionFile);
            state.saveNotice = savedNotice(state.sessionFile);
            noteRecentFile(state, FileKind::Session, state.sessionFile);
        } catch (const renderer::LoadError& e) {
            state.errorMessage = e.what();
        }
    }
    pathField(
        "Image", state.imageFile, FileKind::Image, state,
        "The view as rendered, at the viewport's size (the heatmap when the viewport shows it):\n"
        ".png over the background, 8-bit; .exr or .tif premultiplied float RGBA, as splatlab render writes");
    if (ImGui::Button("Save image")) changes.saveImage = true;
    if (!state.imageSaved.empty()) {
        sameLineIfFits(state.imageSaved.c_str());
        textDisabledWrapped("%s", state.imageSaved.c_str());
    }

    sectionTitle("Splatting");
    changes.settingsChanged |= sliderDouble("Kernel scale", s.kernelScale, 0.3, 2.0, "%.2f");
    numberHint("Reconstruction sigma in voxel spacings; 0.7 keeps the kernels a partition of unity");
    changes.settingsChanged |= sliderDouble("Cutoff", s.cutoffSigmas, 1.0, 5.0, "%.1f sigmas");
    numberHint("Footprints are evaluated out to this many standard deviations");
    changes.settingsChanged |=
        sliderDouble("Density", s.density, 0.01, 100.0, "%.3g", ImGuiSliderFlags_Logarithmic);
    numberHint("Extinction per voxel length at TF opacity 1");
    changes.settingsChanged |= enumCombo("Filter", s.filter,
                                         std::array{renderer::FilterMode::Reconstruction,
                                                    renderer::FilterMode::LowPass, renderer::FilterMode::Ewa,
                                                    renderer::FilterMode::Adaptive},
                                         &renderer::filterModeName);
    hint("reconstruction: kernel only (aliases when minified)\nlow-pass: screen filter only\n"
         "ewa: both convolved, the resampling filter\nadaptive: per patch, the cheapest that suffices");
    if (s.filter == renderer::FilterMode::Adaptive) {
        changes.settingsChanged |= sliderDouble("c_min", s.cMin, 0.05, 1.0, "%.2f");
        numberHint("Reconstruction only where a kernel spans more than 1 px / c_min (paper: 0.3)");
        changes.settingsChanged |= sliderDouble("c_max", s.cMax, 0.0, 8.0, s.cMax <= 0.0 ? "auto" : "%.2f");
        numberHint("Low-pass only where a kernel spans less than 1 px / c_max (0: the paper's 2 (1 + tan^2(fovY/2) (1 + (W/H)^2)), from the image corner)");
        changes.settingsChanged |= numberField(
            "Patch size", s.patchSize, [&] { return ImGui::SliderInt("Patch size", &s.patchSize, 1, 32); });
        numberHint("Slice voxels per patch side; each patch takes one filter (1: every voxel)");
        changes.settingsChanged |= sliderDouble("Hysteresis", s.hysteresis, 0.0, 0.5, "%.2f");
        numberHint("A patch changes filter only when a threshold is crossed by this factor (no flicker while orbiting)");
    }
    changes.settingsChanged |= enumCombo("Compositing", s.compositing,
                                         std::array{renderer::Compositing::SplatEverySample,
                                                    renderer::Compositing::SheetBackToFront,
                                                    renderer::Compositing::SheetFrontToBack,
                                                    renderer::Compositing::XRay},
                                         &renderer::compositingName);
    hint("splat-every-sample: 'over' in slice order (run front to back, reversed, while 'Opaque at' < 1)\n"
         "sheets: a slice sums into a float sheet, sheets composite in order\nxray: additive, order-free");
    using Primitive = renderer::SplatSettings::Primitive;
    if (s.compositing == renderer::Compositing::SplatEverySample) {
        if (s.primitive == Primitive::Tiles) s.primitive = Primitive::Auto;   // tiles sum sheets only
    } else {
        bool tiled = renderer::tiledSplatting(s);
        if (ImGui::Checkbox("Tiled splatting", &tiled)) {
            s.primitive = tiled ? Primitive::Auto : Primitive::Raster;
            changes.settingsChanged = true;
        }
        hint("Compute passes instead of the rasteriser (the default for sheets and X-ray): splats binned to\n"
             "8x8 pixel tiles, each pixel's sheet and image kept in registers. The same image, faster on\n"
             "every machine measured; off: points or quads through the rasteriser");
    }
    if (s.compositing == renderer::Compositing::SheetFrontToBack ||
        s.compositing == renderer::Compositing::SplatEverySample) {
        changes.settingsChanged |= sliderDouble("Opaque at", s.opaqueAlpha, 0.9, 1.0, "%.3f");
        numberHint("Early termination: pixels this opaque take no more splats (1: never)");
        changes.settingsChanged |= numberField("Refresh every", s.opaqueRefreshSlices, [&] {
            return ImGui::SliderInt("Refresh every", &s.opaqueRefreshSlices, 0, 64,
                                    s.opaqueRefreshSlices <= 0 ? "auto" : "%d slices");
        });
        numberHint("How often the opaque pixels are found again (auto: every slice with tiles, every 8 rasterised).\n"
             "Splats whose 8x8 pixel tiles were all opaque are culled before they are drawn; which tiles\n"
             "are opaque is taken at each refresh rasterised, once a chunk of 16 or more slices with tiles");
        changes.settingsChanged |= ImGui::Checkbox("Cull hidden splats", &s.occlusionCulling);
        hint("Drop splats whose tiles (or, rasterised, pixels) were all opaque at the last refresh, before they\n"
             "cost any work; off, they are drawn and early termination alone skips their pixels (the same image).\n"
             "With tiles the culling needs chunks of slices, each ending in a read-back: on by default with\n"
             "llvmpipe, where it pays; off on a GPU, where it cost 1.8x (H100) and 2.1x (H200) at 1920x1080");
    }

    sectionTitle("Split view");
    changes.settingsChanged |= drawSplitViewSection(state, s.compositing);

    sectionTitle("Image-aligned slabs");
    changes.settingsChanged |= drawSlabSection(state);

    sectionTitle("Shading and surfaces");
    ImGui::BeginDisabled(!state.gradientsReady);
    changes.settingsChanged |= enumCombo("Shading", s.shading,
                                         std::array{renderer::SplatSettings::Shading::None,
                                                    renderer::SplatSettings::Shading::PerSplat,
                                                    renderer::SplatSettings::Shading::PerFragment},
                                         &renderer::shadingName);
    hint("Headlight Phong from the gradients: per splat (vertex stage) or per fragment");
    changes.settingsChanged |= sliderDouble("Flatten", s.surfaceFlatten, 1.0, 50.0, "%.1f",
                                            ImGuiSliderFlags_Logarithmic);
    changes.settingsChanged |= sliderDouble("Surface at", s.surfaceGradient, 0.0, 1.0, "%.2f");
    numberHint("Flatten: surface-splat kernels are this much thinner along the gradient (1: off)\n"
         "Surface at: gradient magnitude, as a fraction of the largest, from which a voxel is a surface");
    ImGui::EndDisabled();
    if (!state.gradientsReady) textDisabledWrapped("(gradients not computed yet)");

    sectionTitle("Inspect");
    changes.settingsChanged |= ImGui::Checkbox("GPU counters", &s.counters);
    hint("Count splats per filter and per cull on the GPU (waits for each frame)");
    ImGui::Checkbox("Footprint inspector", &state.inspectFootprint);
    hint("Point at the view: the voxel under the pointer shows its footprint, magnified on the pixel grid:\n"
         "the projected kernel (red), the low-pass filter (green) and their sum, EWA (blue), at the cutoff,\n"
         "with the filter its patch takes and the thresholds it was measured against");
    ImGui::BeginDisabled(!state.preview.available);
    ImGui::Checkbox("Preview level first", &state.preview.whileMoving);
    ImGui::EndDisabled();
    static const std::string previewHint =
        "Volumes of " + std::to_string(PreviewSettings::kMinMegaVoxels) +
        " M voxels or more: after an edit, when the full frame took longer than the frame\n"
        "budget, the view is drawn at half resolution first and the full frame replaces it";
    hint(previewHint.c_str());
    ImGui::BeginDisabled(!state.preview.available);
    changes.settingsChanged |= ImGui::Checkbox("Coarser levels far away", &state.preview.farLevels);
    ImGui::EndDisabled();
    hint("A far view rests on the coarsest preview level whose kernels, twice or four times as wide, still\n"
         "take the low-pass filter (under 1/c_max px at the nearest voxel) and keep the scene's optical\n"
         "mass within 3 %: at 512x512 from about 15 bounding radii, 6 times faster on bonsai");
    if (!state.preview.available)
        textDisabledWrapped("(under %zu M voxels: always drawn in full)", PreviewSettings::kMinMegaVoxels);
    double budget = state.preview.budgetMs > 0.0 ? state.preview.budgetMs : state.preview.defaultBudgetMs;
    if (sliderDouble("Frame budget", budget, 5.0, 2000.0, "%.0f ms", ImGuiSliderFlags_Logarithmic))
        state.preview.budgetMs = budget;
    numberHint("A first image within this after an edit; a newer edit stops a frame that overruns it.\n"
         "Rendering never holds up the editor: the view shows the last finished image meanwhile");

    sectionTitle("Camera");
    changes.cameraChanged |= sliderDouble("Field of view", state.camera.fovYDeg, 10.0, 100.0, "%.0f deg");
    changes.cameraChanged |= drawUpAxisCombo(state.camera.up);
    hint("Axis of the file's world frame shown upwards; CT stacks such as headsq need -z");
    if (ImGui::Button("Reset camera")) {
        renderer::Camera reset;
        reset.up = state.camera.up; // the up axis belongs to the data, not to the view
        state.camera = reset;
        changes.cameraChanged = true;
    }
    ImGui::SameLine();
    changes.frame = ImGui::Button("Frame");
    hint("Frame: move the camera along its line of sight, and pan, until everything the transfer function\n"
         "shows fills the viewport, centred. A double-click in the viewport does the same");
    const renderer::Camera& c = state.camera;
    textDisabledWrapped("azimuth %.1f  elevation %.1f  distance %.2f", c.azimuthDeg, c.elevationDeg, c.distance);

    sectionTitle("3D mouse");
    textDisabledWrapped("%s", state.spaceMouseStatus.empty() ? "not looked for" : state.spaceMouseStatus.c_str());
    SpaceMouseMapping& m = state.spaceMouse;
    ImGui::Checkbox("Navigate with it", &m.enabled);
    hint("Twist: orbit around; tilt forward or back: look from above or below; push or pull: zoom;\n"
         "slide sideways or lift: pan. The knob's deflection sets the speed");
    sliderDouble("Speed", m.speed, 0.1, 10.0, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("Invert rotation", &m.invertRotation);
    sameLineIfFits("Invert moves", ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::Checkbox("Invert moves", &m.invertTranslation);
    hint("Off: the knob turns and moves the object. On: it turns or moves the camera instead");

    ImGui::PopItemWidth();
    return changes;
}

bool applyOrbitInput(renderer::Camera& camera, const OrbitInput& input) {
    const renderer::Camera before = camera;
    if (input.rotateDxPx != 0.0f) {
        const double azimuth =
            std::fmod(camera.azimuthDeg - kOrbitDegPerPx * input.rotateDxPx + 180.0, 360.0);
        camera.azimuthDeg = (azimuth < 0.0 ? azimuth + 360.0 : azimuth) - 180.0;
    }
    if (input.rotateDyPx != 0.0f)
        camera.elevationDeg = std::clamp(camera.elevationDeg + kOrbitDegPerPx * input.rotateDyPx,
                                         -kMaxElevationDeg, kMaxElevationDeg);
    camera.panPx += glm::dvec2(input.panDxPx, input.panDyPx);
    if (input.wheelNotches != 0.0f)
        // A view placed beyond the range (a demo scene's) zooms from where it is, not from the range's end.
        camera.distance = std::clamp(camera.distance * std::pow(kZoomPerNotch, double(input.wheelNotches)),
                                     std::min(kMinDistance, camera.distance), std::max(kMaxDistance, camera.distance));
    return camera.azimuthDeg != before.azimuthDeg || camera.elevationDeg != before.elevationDeg ||
           camera.panPx != before.panPx || camera.distance != before.distance;
}

ViewportResult drawViewportPanel(EditorState& state, unsigned texture, const ViewportOverlay& overlay) {
    const ImGuiIO& io = ImGui::GetIO();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const ImVec2 extent{std::max(avail.x, 1.0f), std::max(avail.y, 1.0f)};
    const ImVec2 end{origin.x + extent.x, origin.y + extent.y};

    // 1. One button over the whole region captures left, right and middle drags (and the wheel).
    ImGui::InvisibleButton("##viewport", extent,
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                               ImGuiButtonFlags_MouseButtonMiddle);
    OrbitInput input;
    if (ImGui::IsItemActive()) {
        const float scaleX = io.DisplayFramebufferScale.x, scaleY = io.DisplayFramebufferScale.y;
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left))
            input.rotateDxPx = io.MouseDelta.x, input.rotateDyPx = io.MouseDelta.y;
        else if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle))
            input.panDxPx = io.MouseDelta.x * scaleX,
            input.panDyPx = io.MouseDelta.y * scaleY; // pan is in render pixels
    }
    if (ImGui::IsItemHovered()) input.wheelNotches = io.MouseWheel;

    ViewportResult result;
    result.cameraChanged = applyOrbitInput(state.camera, input);
    result.frame = ImGui::IsItemHovered() && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left);
    result.widthPx = std::max(1, int(std::lround(extent.x * io.DisplayFramebufferScale.x)));
    result.heightPx = std::max(1, int(std::lround(extent.y * io.DisplayFramebufferScale.y)));
    if (ImGui::IsItemHovered() && !ImGui::IsAnyMouseDown()) {
        result.hoverPx = glm::dvec2((io.MousePos.x - origin.x) * io.DisplayFramebufferScale.x,
                                    (io.MousePos.y - origin.y) * io.DisplayFramebufferScale.y);
        if (state.probe && texture != 0 && !(state.inspectFootprint && state.footprint)) // else the inset says it
            ImGui::SetTooltip("value %.5g at voxel (%d, %d, %d)", double(state.probe->value), state.probe->voxel.x,
                              state.probe->voxel.y, state.probe->voxel.z);
    }

    // 2. The image, or a note saying why there is none. The renderer's texture has row 0 at the top
    //    of the image, so it maps straight onto ImGui's y-down rectangle.
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const auto& bg = state.background;
    draw->AddRectFilled(origin, end, ImGui::GetColorU32(ImVec4(bg[0], bg[1], bg[2], 1.0f)));
    if (!overlay.panes.empty()) {
        drawSplitPanes(overlay, origin.x, origin.y, extent.x, extent.y);
        if (state.inspectFootprint && state.footprint && state.probe)
            drawFootprintInspector(*state.footprint, state.probe->value, end.x, origin.y);
    } else if (texture != 0) {
        const auto id = [](unsigned name) { return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(name)); };
        const bool heatmap = state.showHeatmap && overlay.heatmapTexture != 0;
        const double opacity = heatmap ? std::clamp(state.heatmapOpacity, 0.0, 1.0) : 0.0;
        if (opacity < 1.0) draw->AddImage(id(texture), origin, end);
        if (opacity > 0.0)
            draw->AddImage(id(overlay.heatmapTexture), origin, end, ImVec2(0, 0), ImVec2(1, 1),
                           IM_COL32(255, 255, 255, int(std::lround(opacity * 255.0))));
        if (heatmap && overlay.legend) drawHeatmapLegend(*overlay.legend, origin.x, origin.y, end.x, end.y);
        if (state.inspectFootprint && state.footprint && state.probe)
            drawFootprintInspector(*state.footprint, state.probe->value, end.x, origin.y);
        const std::string perAxis = "level 1/" + std::to_string(1 << state.preview.shownLevel) + " per axis";
        if (state.preview.shown)
            draw->AddText(ImVec2(origin.x + 8.0f, origin.y + 6.0f), ImGui::GetColorU32(ImGuiCol_TextDisabled),
                          state.preview.shownLevel > 1 ? (perAxis + ": finer ones follow").c_str()
                                                     : "preview level: half resolution, the full frame follows");
        else if (state.preview.farLevel > 0)
            draw->AddText(ImVec2(origin.x + 8.0f, origin.y + 6.0f), ImGui::GetColorU32(ImGuiCol_TextDisabled),
                          ("far view, " + perAxis + ": its kernels are under the low-pass threshold").c_str());
    } else {
        // The render thread's first image of a volume shown: "Rendering" until it arrives.
        const std::string note = !state.openingVolume.empty()
                                     ? "Opening " + state.openingVolume.filename().string() + " ..."
                                 : !state.loadedVolume.empty()
                                     ? "Rendering " + state.loadedVolume.filename().string() + " ..."
                                     : "No volume loaded: splatlab editor VOLUME";
        const ImVec2 size = ImGui::CalcTextSize(note.c_str());
        draw->AddText(ImVec2(origin.x + (extent.x - size.x) * 0.5f, origin.y + (extent.y - size.y) * 0.5f),
                      ImGui::GetColorU32(ImGuiCol_TextDisabled), note.c_str());
    }
    return result;
}

namespace {

// The frame's GPU time per pass: a bar of one colour per pass, its share of the bar its share of the
// passes' time (hover for the figures), and the list with each pass's name in its colour.
void drawPassBar(const renderer::FrameStats& f) {
    double total = 0.0;
    for (double ms : f.passMs) total += ms;
    if (!(total > 0.0)) return;
    auto colour = [](int pass) { return passColour(pass, renderer::kGpuPasses); };
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x, height = ImGui::GetFontSize() * 0.8f;
    ImGui::InvisibleButton("##passes", ImVec2(std::max(width, 1.0f), height));
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    float x = origin.x;
    for (int i = 0; i < renderer::kGpuPasses; ++i) {
        const double ms = f.passMs[size_t(i)];
        if (!(ms > 0.0)) continue;
        const float w = float(ms / total) * width;
        draw->AddRectFilled(ImVec2(x, origin.y), ImVec2(x + w, origin.y + height), colour(i));
        const float mouseX = ImGui::GetIO().MousePos.x;
        if (hovered && mouseX >= x && mouseX < x + w)
            ImGui::SetTooltip("%s: %.2f ms, %.0f %% of the passes", renderer::gpuPassName(renderer::GpuPass(i)), ms,
                              100.0 * ms / total);
        x += w;
    }
    drawPassList("passes", f.passMs);
}

} // namespace

void drawStatsPanel(const StatsView& stats) {
    if (!ImGui::BeginTable("##stats", 3, ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingStretchSame))
        return;
    ImGui::TableNextRow();

    // Render column: timings, counts and a frame-time plot.
    ImGui::TableNextColumn();
    const renderer::FrameStats& f = stats.frame;
    // The GPU timer is read a few renders late (no stalls), and the editor renders only on edits.
    if (f.gpuMs > 0.0)
        textWrapped("render  cpu %.2f ms   gpu %.2f ms", f.cpuMs, f.gpuMs);
    else
        textWrapped("render  cpu %.2f ms   gpu (pending)", f.cpuMs);
    if (const int first = std::max(f.firstUsePrograms, f.gpuMs > 0.0 ? f.gpuFirstUsePrograms : 0); first > 0) {
        textDisabledWrapped("first use of %d shader programs: these times include compiling them", first);
        hint("Drivers compile a program when it first draws (llvmpipe: hundreds of ms). The next render\n"
             "of the same settings shows what they cost; Performance > Render continuously shows many");
    }
    drawPassBar(f);
    textWrapped("splats  %llu sent (%zu visible)", static_cast<unsigned long long>(f.splatsDrawn),
                stats.visibleSplats);
    textWrapped("upload  %.1f KiB", double(f.frameUploadBytes) / 1024.0);
    hint("Bytes this frame cost to upload, since the render before it: a TF edit, the 64 KiB table;\n"
         "a turn past a diagonal, that axis's lists; a new scene, all of it; otherwise nothing");
    const size_t sceneVoxels = stats.sceneVoxels ? stats.sceneVoxels : stats.volume ? stats.volume->voxelCount() : 0;
    if (stats.sceneBytes > 0 && sceneVoxels > 0) {
        constexpr double kMiB = 1024.0 * 1024.0;
        textWrapped("memory  scene %.2f bytes a voxel (%.1f MiB)", double(stats.sceneBytes) / double(sceneVoxels),
                    double(stats.sceneBytes) / kMiB);
        textWrapped("        passes %.1f MiB", double(stats.workingBytes) / kMiB);
        hint("GPU memory: the scene (classes, the view axis's lists, gradients) and the buffers tiled\n"
             "frames work in (records and lists of the largest chunk of slices so far)");
    }
    textWrapped("drawn as  %s", renderer::primitiveName(f).c_str());
    hint("Rasterised, each slice takes point sprites where its footprints fit the driver's point size\n"
         "and are round enough, else two-triangle quads (close up, the near slices)");
    if (const std::string splits = renderer::tileSplitsText(f); !splits.empty()) {
        textDisabledWrapped("%s", splits.c_str());
        hint("A chunk of slices whose tile lists exceed the texel buffer they are read through\n"
             "(GL_MAX_TEXTURE_BUFFER_SIZE) or 256 MiB goes in parts, and so does one whose busiest tile\n"
             "has more entries than the driver lets a shader's loops walk (llvmpipe: 65,535): the same\n"
             "image, a little slower");
    }
    if (f.adaptiveAs != renderer::FilterMode::Adaptive)
        textWrapped("adaptive  every patch %s at this depth range", renderer::filterModeName(f.adaptiveAs));
    if (f.hasCounters) {
        const renderer::SplatCounters& c = f.counters;
        textWrapped("filters recon %llu  low-pass %llu  ewa %llu", (unsigned long long)c.drawnPerMode[0],
                    (unsigned long long)c.drawnPerMode[1], (unsigned long long)c.drawnPerMode[2]);
        textWrapped("culled  transparent %llu  near %llu  offscreen %llu  huge %llu",
                    (unsigned long long)c.culledTransparent, (unsigned long long)c.culledNear,
                    (unsigned long long)c.culledOffscreen, (unsigned long long)c.culledHuge);
        textWrapped("near layer %llu kernels  dropped %llu", (unsigned long long)c.nearLayer,
                    (unsigned long long)c.droppedNear);
        if (c.droppedNear > 0)
            hint("Kernels at the near plane are integrated along each pixel's ray, up to a bound a frame\n"
                 "(kMaxNearKernels, renderer/oracle/near_layer.h); the rest are left out of the image");
        textWrapped("hidden  behind opaque tiles %llu", (unsigned long long)c.culledOccluded);
        textWrapped("fragments %llu (all passes)", (unsigned long long)f.fragments);
    }

    // Volume column.
    ImGui::TableNextColumn();
    if (const renderer::Volume* v = stats.volume) {
        textWrapped("volume  %s", v->name.c_str());
        textWrapped("dims    %d x %d x %d  %s", v->dims.x, v->dims.y, v->dims.z,
                    renderer::voxelTypeName(v->type));
        textWrapped("spacing %.3g x %.3g x %.3g", v->spacing.x, v->spacing.y, v->spacing.z);
        textWrapped("range   [%g, %g]", double(v->range.lo), double(v->range.hi));
        if (v->resampled) {
            textWrapped("axes    sheared, resampled");
            hint("The file's axes are not orthogonal (a CT's gantry tilt, for one): its voxels were resampled\n"
                 "(trilinear) onto a grid along the world axes, the size shown above, so the picture is in the\n"
                 "file's world frame. Grid points outside the scan take the data's minimum");
        } else if (v->axesNotDrawn()) {
            textDisabledWrapped("axes    sheared, not applied");
            hint("The file's axes are not orthogonal; SplatLab draws the volume along its index axes,\n"
                 "so this picture may be turned or skewed against the file's world frame");
        } else if (v->directions != glm::dmat3(1.0)) {
            // The rotation's angle from its trace: 1 + 2 cos(angle).
            const double trace = v->directions[0][0] + v->directions[1][1] + v->directions[2][2];
            // %g: a scanner's slight tilt (0.0057 degrees) must not read as 0.0.
            textWrapped("axes    oblique, turned %.3g degrees",
                        glm::degrees(std::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0))));
            hint("The file's axes are turned against its world frame. The view turns with them, so the\n"
                 "camera orbits in the file's world frame while slices follow the volume's own axes");
        }
    } else {
        textDisabledWrapped("no volume loaded");
    }

    // GL column.
    ImGui::TableNextColumn();
    textWrapped("GL_RENDERER  %s", stats.glRenderer.c_str());
    textWrapped("ui      %.1f fps", double(ImGui::GetIO().Framerate));
    if (!stats.levels.empty()) {
        ImGui::TextUnformatted(stats.levels.c_str());
        hint("Levels of detail: after an edit the view comes first from the finest level whose last time\n"
             "fits the frame budget (Settings > Inspect), then finer ones replace it up to the full frame.\n"
             "RMSE: of the level's last image against the full frame that replaced it (0..1 colour units)");
    }
    ImGui::EndTable();
}

void drawHelpPanel() {
    bulletWrapped("Left drag in the viewport: orbit");
    bulletWrapped("Right or middle drag: pan");
    bulletWrapped("Wheel: zoom (distance %.2f to %.0f bounding radii)", kMinDistance, kMaxDistance);
    bulletWrapped("Double-click: frame everything visible (Settings > Camera > Frame)");
    bulletWrapped("Hover the view: the value of the voxel under the mouse, marked on the transfer function");
    bulletWrapped("Drag the bars between regions to resize them");
    bulletWrapped("Transfer function curve: drag a point, click empty space to add one, right-click to remove");
    bulletWrapped("3D mouse: twist to orbit, tilt to look from above or below, push or pull to zoom, slide to pan");
    bulletWrapped("Performance tab: render continuously (and spin) to watch frame times; hover the chart");
    bulletWrapped("Volumes of %zu M voxels or more show a half-resolution preview level first when a frame "
                  "is slow (Settings > Inspect > Preview level first, Frame budget)",
                  PreviewSettings::kMinMegaVoxels);
    bulletWrapped("Ctrl+Z, Ctrl+Y: undo, redo a transfer-function edit (while its panel has focus)");
    bulletWrapped("Drop a volume, a transfer function (.json, or Slicer's presets .xml) or a session on the "
                  "window to open it");
}

void drawErrorModal(EditorState& state) {
    if (!state.errorMessage.empty() && !ImGui::IsPopupOpen("Error")) ImGui::OpenPopup("Error");
    if (!ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
    ImGui::TextUnformatted(state.errorMessage.c_str());
    ImGui::PopTextWrapPos();
    if (ImGui::Button("OK", ImVec2(ImGui::GetFontSize() * 6.0f, 0.0f))) {
        state.errorMessage.clear();
        ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
}

bool drawWindowSection(EditorState& state, const WindowView& view) {
    sectionTitle("Window");
    if (!view.volume || !view.histogram || view.histogram->counts.empty()) {
        ImGui::TextDisabled("no volume loaded");
        return false;
    }
    const renderer::ValueRange range = view.volume->range;
    renderer::WindowSettings& w = state.window;
    const renderer::WindowSettings before = w;

    // 1. Mode: data range, percentile 1-99, custom lo..hi in data units.
    using renderer::WindowMode;
    for (auto mode : {WindowMode::DataRange, WindowMode::Percentile, WindowMode::Custom}) {
        if (mode != WindowMode::DataRange)   // the circle is a frame high, then inner spacing
            sameLineIfFits(renderer::windowModeName(mode), ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x);
        if (ImGui::RadioButton(renderer::windowModeName(mode), w.mode == mode) && w.mode != mode) {
            if (mode == renderer::WindowMode::Custom) w.custom = view.window;   // start from what is shown
            w.mode = mode;
        }
    }
    hint("Which data values map onto the transfer function's 0..1\n"
         "percentile 1-99: outliers (metal, air) do not squash the tissue range");
    if (w.mode == renderer::WindowMode::Custom) {
        const float speed = std::max((range.hi - range.lo) / 500.0f, 1e-6f);
        float lo = w.custom.lo, hi = w.custom.hi;
        // Two fields, each through numberField (DragFloatRange2 would take Ctrl+click to type).
        const float half = (ImGui::CalcItemWidth() - ImGui::GetStyle().ItemInnerSpacing.x) * 0.5f;
        ImGui::SetNextItemWidth(half);
        bool edited = numberField("##window_low", lo, [&] {
            return ImGui::DragFloat("##window_low", &lo, speed, range.lo, hi, "%.4g",
                                    ImGuiSliderFlags_AlwaysClamp);
        });
        numberHint("Low end of the window, in the data's own units (e.g. Hounsfield units for CT)");
        ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
        ImGui::SetNextItemWidth(half);
        edited |= numberField("##window_high", hi, [&] {
            return ImGui::DragFloat("##window_high", &hi, speed, lo, range.hi, "%.4g",
                                    ImGuiSliderFlags_AlwaysClamp);
        });
        numberHint("High end of the window, in the data's own units");
        ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
        ImGui::TextUnformatted("Low / high");
        if (edited && lo < hi) w.custom = {lo, hi};
    }
    // Three ranges, each kept whole on a line.
    const std::pair<const char*, renderer::ValueRange> ranges[] = {
        {"window", view.window}, {"data", range}, {"p1..p99", view.percentile}};
    for (const auto& [name, r] : ranges) {
        char text[96];
        std::snprintf(text, sizeof text, "%s %.4g .. %.4g", name, double(r.lo), double(r.hi));
        if (name != ranges[0].first) sameLineIfFits(text);
        ImGui::TextDisabled("%s", text);
    }

    // 2. Histogram: one bar per bin (log or linear counts), the window shaded, hover for the values.
    ImGui::Checkbox("Log scale", &state.histogramLog);
    const renderer::Histogram& h = *view.histogram;
    // Four lines tall: at 1280 x 800 the TF column then fits without a scrollbar even with a save notice
    // and the 2D TF header, so the curve keeps its width (a scrollbar would move every point sideways).
    const ImVec2 size(std::max(ImGui::GetContentRegionAvail().x, 32.0f), ImGui::GetFontSize() * 4.0f);
    ImGui::InvisibleButton("##histogram", size);
    const ImVec2 p0 = ImGui::GetItemRectMin(), p1 = ImGui::GetItemRectMax();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(p0, p1, ImGui::GetColorU32(ImGuiCol_FrameBg));
    const auto height = [&](uint64_t count) {
        return state.histogramLog ? std::log1p(double(count)) : double(count);
    };
    double peak = 0;
    for (uint64_t c : h.counts) peak = std::max(peak, height(c));
    const size_t bins = h.counts.size();
    const float binW = (p1.x - p0.x) / float(bins);
    for (size_t i = 0; i < bins; ++i) {
        if (h.counts[i] == 0 || peak <= 0) continue;
        const float top = p1.y - float(height(h.counts[i]) / peak) * (p1.y - p0.y);
        draw->AddRectFilled(ImVec2(p0.x + binW * float(i), top), ImVec2(p0.x + binW * float(i + 1), p1.y),
                            ImGui::GetColorU32(ImGuiCol_PlotHistogram));
    }
    const double span = double(h.range.hi) - double(h.range.lo);
    const auto xOf = [&](float value) {
        const double t = span > 0 ? (double(value) - h.range.lo) / span : 0.0;
        return p0.x + float(std::clamp(t, 0.0, 1.0)) * (p1.x - p0.x);
    };
    const float wx0 = xOf(view.window.lo), wx1 = xOf(view.window.hi);
    const ImU32 shade = IM_COL32(0, 0, 0, 110), marker = IM_COL32(255, 200, 80, 255);
    draw->AddRectFilled(p0, ImVec2(wx0, p1.y), shade);
    draw->AddRectFilled(ImVec2(wx1, p0.y), p1, shade);
    draw->AddLine(ImVec2(wx0, p0.y), ImVec2(wx0, p1.y), marker, 1.5f);
    draw->AddLine(ImVec2(wx1, p0.y), ImVec2(wx1, p1.y), marker, 1.5f);
    if (ImGui::IsItemHovered()) {
        const float mx = ImGui::GetIO().MousePos.x;
        const size_t bin = size_t(std::clamp(int((mx - p0.x) / binW), 0, int(bins) - 1));
        const double value = h.range.lo + span * double(mx - p0.x) / double(p1.x - p0.x);
        const double width = span / double(bins);
        ImGui::SetTooltip("value %.5g (data units)\nbin %.5g .. %.5g: %llu voxels", value,
                          h.range.lo + width * double(bin), h.range.lo + width * double(bin + 1),
                          static_cast<unsigned long long>(h.counts[bin]));
    }
    return w.mode != before.mode ||
           (w.mode == renderer::WindowMode::Custom &&
            (w.custom.lo != before.custom.lo || w.custom.hi != before.custom.hi));
}

bool drawProgressModal(const char* title, const std::string& text, double fraction, bool running) {
    if (running && !ImGui::IsPopupOpen(title)) ImGui::OpenPopup(title);
    if (!ImGui::BeginPopupModal(title, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return false;
    bool cancel = false;
    if (!running) {
        ImGui::CloseCurrentPopup();
    } else {
        ImGui::TextUnformatted(text.c_str());
        ImGui::ProgressBar(float(std::clamp(fraction, 0.0, 1.0)), ImVec2(ImGui::GetFontSize() * 20.0f, 0.0f));
        cancel = ImGui::Button("Cancel", ImVec2(ImGui::GetFontSize() * 6.0f, 0.0f));
    }
    ImGui::EndPopup();
    return cancel;
}

} // namespace ui
