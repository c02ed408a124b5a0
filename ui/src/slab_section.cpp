// Settings > Image-aligned slabs (see slab_section.h).
#include "slab_section.h"

#include "widgets.h"

#include <imgui.h>

namespace ui {

bool drawSlabSection(EditorState& state) {
    SlabView& slabs = state.slabs;
    const renderer::SplatSettings& s = state.settings;
    // What the slabs cannot draw (renderer/oracle/image_slabs.h): said here, not as an error each frame.
    const char* unavailable = s.compositing == renderer::Compositing::XRay ? "not with X-ray compositing (no order)"
                              : s.surfaceFlatten > 1.0                     ? "not with surface splats (Flatten 1)"
                              : state.split.enabled                        ? "not in a split view"
                                                                           : nullptr;
    bool changed = false;
    ImGui::BeginDisabled(unavailable != nullptr);
    changed |= ImGui::Checkbox("Slabs when still", &slabs.enabled);
    hint("Once the view rests, draw it again in slabs parallel to the image, each kernel's share of a slab\n"
         "integrated along the ray: no popping when the view turns, no object-aligned rings. It replaces the\n"
         "sheets' image when done (seconds on a CPU driver); any move shows the sheets again");
    ImGui::BeginDisabled(!slabs.enabled);
    changed |= sliderDouble("Thickness", slabs.thickness, kSlabThicknessLo, kSlabThicknessHi, "%.2f voxels",
                            ImGuiSliderFlags_Logarithmic);
    numberHint("Slab thickness in voxel spacings: thinner is closer to the ground truth and slower\n"
               "(0.5: docs/accuracy.md's thickness curve)");
    changed |= ImGui::Checkbox("Post-classified", &slabs.postClassified);
    hint("The TF applied to each slab's reconstructed value (sharp TF edges stay sharp), not to each voxel\n"
         "before reconstruction. Takes a 1D TF without gradient opacity");
    ImGui::EndDisabled();
    ImGui::EndDisabled();
    if (unavailable) textDisabledWrapped("%s", unavailable);
    else if (slabs.enabled && !slabs.status.empty()) textDisabledWrapped("%s", slabs.status.c_str());
    return changed;
}

} // namespace ui
