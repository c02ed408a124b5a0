// Uniforms and the adaptive classifier, shared by the splat vertex stage and the patch-mode pass.
uniform ivec3 uDims;
uniform vec3 uSpacing;        // object position of voxel ijk is origin + spacing * ijk
uniform mat3 uViewFromObject; // W
uniform vec3 uTranslation;    // W origin + d: camera position of voxel (0,0,0)
uniform float uFPx;
uniform float uNear;
uniform int uFilter;          // 0 reconstruction, 1 low-pass, 2 EWA, 3 adaptive (classifier.h)
uniform bool uOrtho;          // constant affine projection diag(f, f, 1)
uniform int uAxis;            // traversal axis: slices and patches lie across it
uniform int uPatchSize;
uniform float uReconAbovePx, uLowPassBelowPx, uSigmaMin, uSigmaMax;

uniform float uHysteresis;

// previous: last frame's filter (3: none), for hysteresis, as classifyDepth() on the CPU.
int classifyDepth(float u2, int previous) {
    if (!uOrtho && !(u2 > uNear)) return 0;
    float pxPerUnit = uOrtho ? uFPx : uFPx / u2;
    float reconAbove = uReconAbovePx, lowPassBelow = uLowPassBelowPx;
    if (uHysteresis > 0.0 && previous != 3) {   // enter by 1 + h, leave by 1 / (1 + h)
        float band = 1.0 + uHysteresis;
        reconAbove = previous == 0 ? reconAbove / band : reconAbove * band;
        lowPassBelow = previous == 1 ? lowPassBelow * band : lowPassBelow / band;
    }
    if (uSigmaMin * pxPerUnit > reconAbove) return 0;
    if (uSigmaMax * pxPerUnit < lowPassBelow) return 1;
    return 2;
}

// The patch's filter from its four corner voxels, as classifyPatch() does on the CPU.
int classifyPatch(ivec3 ijk, int previous) {
    int a = (uAxis + 1) % 3, b = (uAxis + 2) % 3;
    int a0 = ijk[a] / uPatchSize * uPatchSize, b0 = ijk[b] / uPatchSize * uPatchSize;
    int a1 = min(a0 + uPatchSize - 1, uDims[a] - 1), b1 = min(b0 + uPatchSize - 1, uDims[b] - 1);
    int mode = 2;
    for (int corner = 0; corner < 4; ++corner) {
        ivec3 c = ijk;
        c[a] = (corner & 1) != 0 ? a1 : a0;
        c[b] = (corner & 2) != 0 ? b1 : b0;
        int m = classifyDepth((uViewFromObject * (uSpacing * vec3(c)) + uTranslation).z, previous);
        if (corner == 0) mode = m;
        else if (m != mode) return 2;
    }
    return mode;
}

int resolveFilter(ivec3 ijk, int previous) { return uFilter == 3 ? classifyPatch(ijk, previous) : uFilter; }
