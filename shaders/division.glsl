// Division rounded to nearest, as IEEE 754 rounds it and so as the CPU backend divides
// (included by mesh_positions.glsl and mesh_triangle.glsl).
//
// GPU and CPU maps agree to the bit only if both divide exactly, and GLSL lets `/` be 2.5 ULP
// off. NVIDIA's float `/` is (an H100, driver 580: 21,145 of 70,218 quotients differed from
// IEEE, GpuArithmetic), and GLSL's fma() need not be fused (llvmpipe's is not), so neither a
// plain `/` nor the usual fma-based correction can be trusted. Here the quotient `/` gives is
// corrected with the exact residual a - q b, found by Dekker's product from + and * alone,
// which GLSL rounds correctly and which `precise` keeps from being fused or reordered: one
// correction brings q within an ulp of a / b, and the exact residual then says whether a / b
// lies nearer q's neighbour (a quotient is never a midpoint). Where `/` is already exact
// (llvmpipe; NVIDIA's double `/`) q never moves. Floats go through doubles: rounding a / b to
// double and then to float is rounding it to float, since 53 >= 2 * 24 + 2. Needs a, b finite,
// b non-zero, both far from the ends of the double range (every call divides pixel
// coordinates, sizes and areas).
#ifndef MULTICAGE_DIVISION_GLSL
#define MULTICAGE_DIVISION_GLSL

// a * b = hi + lo exactly (Dekker's product with Veltkamp's split at 27 bits).
void twoProduct(double a, double b, out double hi, out double lo) {
    precise double ca = 134217729.0LF * a, cb = 134217729.0LF * b;
    precise double ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
    precise double p = a * b;
    precise double e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    hi = p, lo = e;
}

// a - q b; exact when q is within an ulp of a / b (the residual is then a double).
double divisionResidual(double a, double b, double q) {
    double p, e;
    twoProduct(q, b, p, e);
    precise double r = (a - p) - e;
    return r;
}

// The nearest double to a / b, from `start` within 2.5 ulps of it (what `/` gives).
double divideRNFrom(double a, double b, double start) {
    precise double q = start;
    q = q + divisionResidual(a, b, q) / b;  // within an ulp of a / b
    const double r = divisionResidual(a, b, q);
    // a / b = q + r / b. The neighbour of q on that side lies an ulp away, or half an ulp when
    // q is a power of two and the neighbour is nearer zero. (A loop that stops as soon as q
    // stands, one residual where `/` is exact, was slower on llvmpipe: 125 -> 156 ms for the
    // positions and raster passes at 1024x768.)
    int exponent;
    const double mantissa = frexp(q, exponent);
    const bool up = (r > 0.0LF) == (b > 0.0LF);
    const bool towardZero = up != (q > 0.0LF);
    precise double gap = ldexp(abs(mantissa) == 0.5LF && towardZero ? 0.5LF : 1.0LF, exponent - 53);
    if (abs(r) > abs(b) * (0.5LF * gap)) q += up ? gap : -gap;
    return q;
}

double divideRN(double a, double b) {
    return divideRNFrom(a, b, a / b);
}

float divideRN(float a, float b) {
    return float(divideRN(double(a), double(b)));
}

#endif
