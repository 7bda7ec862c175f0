#version 430 core
// Mean value binding on the GPU (paper Algorithm 1; Hormann & Floater 2006), one invocation
// per grid node, written straight into the packed coefficient texture (paper Eq. 6-7).
// Constants inserted by the library: GRID_W, GRID_H, GRID_STEP, IMAGE_W, IMAGE_H, POLYGONS,
// BLOCK_COLS, BLOCKS_PER_LAYER, LAYERED, COEFF_FORMAT (rgba32f or rgba16f).
// The kernel between the template markers is instantiated twice by the library: in float
// (REAL = float, EXACT = false) for the bulk, and in double (REAL = double, EXACT = true) for
// nodes on or near a vertex or an edge and for nodes whose weights nearly cancel; this is the
// same split as the CPU bind(), so both agree to float rounding.

layout(local_size_x = 8, local_size_y = 8) in;

// Rest vertices in coefficient order: user polygons, then the 4 frame corners.
layout(std430, binding = 0) readonly buffer Vertices { vec2 vertices[]; };
// Per polygon (frame last): first coefficient, vertex count, orientation sign (+1/-1), 0.
// The sign makes the raw weights those of the polygon oriented by the orientation rule.
layout(std430, binding = 1) readonly buffer Polygons { ivec4 polygons[]; };

#if LAYERED
layout(COEFF_FORMAT, binding = 0) writeonly uniform image2DArray coefficientImage;
#else
layout(COEFF_FORMAT, binding = 0) writeonly uniform image2D coefficientImage;
#endif
// |sum_j w_j| / sum_j |w_j| per node (the conditioning Binding::minConditioning reports).
layout(r32f, binding = 1) writeonly uniform image2D conditioningImage;
layout(location = 0) uniform int firstRow;  // dispatches go in bands of rows

void storeBlock(int b, ivec2 g, vec4 v) {
    const int slot = b % BLOCKS_PER_LAYER;
    const ivec2 t = g + ivec2(slot % BLOCK_COLS, slot / BLOCK_COLS) * ivec2(GRID_W, GRID_H);
#if LAYERED
    imageStore(coefficientImage, ivec3(t, b / BLOCKS_PER_LAYER), v);
#else
    imageStore(coefficientImage, t, v);  // paper Eq. 6
#endif
}

//@template-begin
// Pass 1: the sum and absolute sum of all raw weights. Returns 0 (general), 1 (the node is
// on polygon exactPoly: vertex exactI, or edge (exactI, exactJ) with weights wi, wj), or 2
// (too close to a vertex, an edge or a cancellation for this precision).
int sumPass_PREC(REAL2 x, out REAL sum, out REAL absSum, out int exactPoly, out int exactI,
                 out int exactJ, out REAL wi, out REAL wj) {
    sum = REAL(0);
    absSum = REAL(0);
    exactPoly = exactI = exactJ = -1;
    wi = wj = REAL(0);
    for (int p = 0; p < POLYGONS; ++p) {
        const int first = polygons[p].x, n = polygons[p].y;
        const REAL sign = REAL(polygons[p].z);
        if (EXACT) {
            // The exact policy of the CPU's meanValueWeights: vertices first, then edges.
            const REAL kOn = REAL(1e-9);
            for (int i = 0; i < n; ++i)
                if (length(REAL2(vertices[first + i]) - x) <= kOn) {
                    exactPoly = p, exactI = i, wi = REAL(1);
                    return 1;
                }
            for (int i = 0; i < n; ++i) {
                const int j = i + 1 == n ? 0 : i + 1;
                const REAL2 si = REAL2(vertices[first + i]) - x, sj = REAL2(vertices[first + j]) - x;
                const REAL ri = length(si), rj = length(sj);
                const REAL A = si.x * sj.y - si.y * sj.x, D = dot(si, sj);
                if (D < REAL(0) && abs(A) <= kOn * (ri + rj)) {
                    exactPoly = p, exactI = i, exactJ = j;
                    wi = rj / (ri + rj), wj = ri / (ri + rj);  // linear along the edge
                    return 1;
                }
            }
        }
        REAL2 si = REAL2(vertices[first]) - x;
        REAL ri = length(si);
        const REAL2 sl = REAL2(vertices[first + n - 1]) - x;
        const REAL rl = length(sl);
        REAL A = sl.x * si.y - sl.y * si.x, D = dot(sl, si);
        // t = tan(alpha/2) in the form that is stable on each side of D = 0.
        REAL tPrev = D > REAL(0) ? A / (rl * ri + D) : (rl * ri - D) / A;
        for (int i = 0; i < n; ++i) {
            const int j = i + 1 == n ? 0 : i + 1;
            const REAL2 sj = REAL2(vertices[first + j]) - x;
            const REAL rj = length(sj);
            A = si.x * sj.y - si.y * sj.x;
            D = dot(si, sj);
            if (!EXACT && (ri < REAL(1e-3) || (D <= REAL(0) && abs(A) < REAL(1e-4) * ri * rj)))
                return 2;
            const REAL t = D > REAL(0) ? A / (ri * rj + D) : (ri * rj - D) / A;
            const REAL w = sign * (tPrev + t) / ri;  // w_i = (t_{i-1} + t_i) / r_i
            sum += w;
            absSum += abs(w);
            tPrev = t, si = sj, ri = rj;
        }
    }
    if (!EXACT && (isinf(absSum) || isnan(absSum) || abs(sum) < REAL(1e-4) * absSum)) return 2;
    return 0;
}

// Pass 2: the same raw weights times invSum (Algorithm 1's normalisation), or the exact
// vertex/edge values of polygon exactPoly and 0 elsewhere, four coefficients per texel.
void writePass_PREC(REAL2 x, ivec2 g, REAL invSum, int exactPoly, int exactI, int exactJ,
                    REAL wi, REAL wj) {
    vec4 acc = vec4(0.0);
    int c = 0;
    for (int p = 0; p < POLYGONS; ++p) {
        const int first = polygons[p].x, n = polygons[p].y;
        const REAL sign = REAL(polygons[p].z);
        REAL2 si = REAL2(vertices[first]) - x;
        REAL ri = length(si);
        REAL tPrev = REAL(0);
        if (exactPoly < 0) {
            const REAL2 sl = REAL2(vertices[first + n - 1]) - x;
            const REAL rl = length(sl);
            const REAL A = sl.x * si.y - sl.y * si.x, D = dot(sl, si);
            tPrev = D > REAL(0) ? A / (rl * ri + D) : (rl * ri - D) / A;
        }
        for (int i = 0; i < n; ++i, ++c) {
            REAL value = REAL(0);
            if (exactPoly >= 0) {
                if (p == exactPoly) value = i == exactI ? wi : (i == exactJ ? wj : REAL(0));
            } else {
                const int j = i + 1 == n ? 0 : i + 1;
                const REAL2 sj = REAL2(vertices[first + j]) - x;
                const REAL rj = length(sj);
                const REAL A = si.x * sj.y - si.y * sj.x, D = dot(si, sj);
                const REAL t = D > REAL(0) ? A / (ri * rj + D) : (ri * rj - D) / A;
                value = sign * (tPrev + t) / ri * invSum;
                tPrev = t, si = sj, ri = rj;
            }
            acc[c & 3] = float(value);
            if ((c & 3) == 3) {
                storeBlock(c >> 2, g, acc);
                acc = vec4(0.0);
            }
        }
    }
    if ((c & 3) != 0) storeBlock(c >> 2, g, acc);
}
//@template-end

void main() {
    const ivec2 g = ivec2(gl_GlobalInvocationID.x, int(gl_GlobalInvocationID.y) + firstRow);
    if (g.x >= GRID_W || g.y >= GRID_H) return;
    const vec2 x = vec2(min(g * GRID_STEP, ivec2(IMAGE_W - 1, IMAGE_H - 1)));
    float sum, absSum, wi, wj;
    int exactPoly, exactI, exactJ;
    float kappa;
    if (sumPass_f(x, sum, absSum, exactPoly, exactI, exactJ, wi, wj) == 0) {
        // CPU bind() multiplies by the float reciprocal too: the same rounding.
        writePass_f(x, g, 1.0 / sum, -1, -1, -1, 0.0, 0.0);
        kappa = abs(sum) / absSum;
    } else {
        double dsum, dabs, dwi, dwj;
        const dvec2 dx = dvec2(x);
        if (sumPass_d(dx, dsum, dabs, exactPoly, exactI, exactJ, dwi, dwj) == 1) {
            writePass_d(dx, g, 1.0lf, exactPoly, exactI, exactJ, dwi, dwj);
            kappa = 1.0;
        } else {
            // An exact cancellation leaves the node at rest (all zero), as on the CPU.
            writePass_d(dx, g, dsum == 0.0lf ? 0.0lf : 1.0lf / dsum, -1, -1, -1, 0.0lf, 0.0lf);
            kappa = dsum == 0.0lf ? 0.0 : float(abs(dsum) / dabs);
        }
    }
    imageStore(conditioningImage, g, vec4(kappa));
}
