// A tile composite's sheet into its image: one definition for both layouts (tile_composite.comp,
// a column per invocation; tile_composite_pixels.comp, a pixel per invocation).

// (sum c tau, sum tau) -> premultiplied colour of alpha 1 - exp(-sum tau), as the sheet composite.
vec4 sheetRgba(vec4 q) {
    if (!(q.a > 0.0)) return vec4(0.0);
    float a = q.a < 1e-3 ? q.a * (1.0 - 0.5 * q.a) : 1.0 - exp(-q.a);
    return vec4(q.rgb / q.a * a, a);
}

vec4 compositeSheet(vec4 image, vec4 sheet, bool frontToBack) {
#ifdef XRAY
    return image + sheet;
#else
    vec4 s = sheetRgba(sheet);
    return frontToBack ? image + (1.0 - image.a) * s : s + (1.0 - s.a) * image;
#endif
}
