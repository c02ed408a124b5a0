// The CPU oracle's compositing of premultiplied RGBA, one place for the object-aligned sheets, the
// image-aligned slabs and the near layer.
#pragma once
#include <cmath>

namespace renderer {

// "Over" of premultiplied (c, a) onto what lies behind it in dst.
inline void over(double* dst, const double* c, double a) {
    for (int k = 0; k < 3; ++k) dst[k] = c[k] + (1.0 - a) * dst[k];
    dst[3] = a + (1.0 - a) * dst[3];
}

// "Under": premultiplied (c, a) behind what dst already holds (front to back).
inline void under(double* dst, const double* c, double a) {
    for (int k = 0; k < 3; ++k) dst[k] += (1.0 - dst[3]) * c[k];
    dst[3] += (1.0 - dst[3]) * a;
}

// Premultiplied RGBA of a sheet pixel holding (sum c tau, sum tau): alpha 1 - exp(-sum tau), colour
// the tau-weighted mean.
inline void sheetColour(const double* q, double* c, double& a) {
    a = -std::expm1(-q[3]);
    for (int k = 0; k < 3; ++k) c[k] = q[k] / q[3] * a;
}

} // namespace renderer
