// How many iterations the driver lets one invocation's loops run (measureLoopLimit()): a loop of uN
// iterations counts them; llvmpipe stops every loop of a shader at 65535 together.
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Result { uint iterations; };
uniform uint uN;
void main() {
    uint n = 0u;
    for (uint i = 0u; i < uN; ++i) ++n;
    iterations = n;
}
