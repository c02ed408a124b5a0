// erf in float for the closed-form integrals of Gaussians along rays (the near layer, the image-aligned
// slabs). Abramowitz and Stegun 7.1.26: |error| below 1.5e-7, under float's resolution of the sums.
float erfApprox(float x) {
    float t = 1.0 / (1.0 + 0.3275911 * abs(x));
    float p = ((((1.061405429 * t - 1.453152027) * t + 1.421413741) * t - 0.284496736) * t + 0.254829592) * t;
    return sign(x) * (1.0 - p * exp(-x * x));
}
