// The footprint's quadratic form at pixel offset (dx, dy) from its centre: e = a dx^2 + 2 b dx dy + c dy^2
// for conic (a, b, c). One definition for the fragment stage and the tile composite.
float conicForm(vec3 q, float dx, float dy) { return q.x * dx * dx + 2.0 * q.y * dx * dy + q.z * dy * dy; }
