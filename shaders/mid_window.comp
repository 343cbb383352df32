#version 460
#extension GL_GOOGLE_include_directive : require
// mid.window (DESIGN.md step 5): the space-time window of the solver from
// the keyframe store, then what every iteration reads, exactly as
// mid_window_build() (engine/disparity/mid_window.c, docs/method.md Sec. 4):
// flow links A_f, A_b with their occlusion masks, the transposes as CSR rows
// (counted, scanned by mid_scan.comp, filled, sorted by source so every sum
// has the CPU's order), edge weights, the targets of c_t and c_a, and the
// flow chains of the line preconditioner.
#include "mid_arena.glsl"
// Each step reads what the steps before it wrote through the texel views
// (mid_arena.glsl R_*), except the sort, which reads its own rows back.
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
MID_ELEMENT_LAYOUT;

// Paper 4.4's depth test: the same surface when the depths differ by less
// than the relative tolerance.
bool same_surface(float z0, float z1)
{
    if (!(z0 > 0.0) || !(z1 > 0.0) || isinf(z0) || isinf(z1) || isnan(z0) || isnan(z1))
        return false;
    return abs(log(z1 / z0)) <= pc.log_tol;
}

// The flows there and back cancel (keeps fast motion in depth linked).
bool round_trip(uint there, uint back)
{
    vec2 a = R_FLOW(there), b = R_FLOW(back);
    float dx = a.x + b.x, dy = a.y + b.y;
    float lim = pc.flow_tol + 0.1 * (abs(a.x) + abs(a.y));
    return dx * dx + dy * dy <= lim * lim;
}

// Row i = element (x, y, k) of A_f (dir 0) or A_b (dir 1), as link_make().
mid_link link_make(uint i, int x, int y, int k, uint dir)
{
    mid_link l;
    l.base = 0u;
    l.fx = 0.0;
    l.fy = 0.0;
    l.mask = 0u;
    int kk = k + (dir == 0u ? 1 : -1);
    if (kk < 0 || kk >= int(pc.nt))
        return l;
    uint there = dir * pc.cap + i, back_off = (1u - dir) * pc.cap;
    vec2 u = R_FLOW(there);
    float tx = float(x) + u.x, ty = float(y) + u.y;
    if (!(tx >= -0.5 && tx <= float(pc.nx) - 0.5 && ty >= -0.5 && ty <= float(pc.ny) - 0.5))
        return l; // out of frame, or NaN
    tx = min(max(tx, 0.0), float(pc.nx - 1u));
    ty = min(max(ty, 0.0), float(pc.ny - 1u));
    int x0 = min(int(floor(tx)), int(pc.nx) - 2), y0 = min(int(floor(ty)), int(pc.ny) - 2);
    l.fx = tx - float(x0);
    l.fy = ty - float(y0);
    l.base = uint(kk) * pc.ns + uint(y0) * pc.nx + uint(x0);
    float raw[4] = float[4]((1.0 - l.fx) * (1.0 - l.fy), l.fx * (1.0 - l.fy), (1.0 - l.fx) * l.fy, l.fx * l.fy);
    uint idx[4] = uint[4](l.base, l.base + 1u, l.base + pc.nx, l.base + pc.nx + 1u);
    float kept = 0.0, z0 = R_DEPTH(i), id = R_ID(i);
    for (uint t = 0u; t < 4u; t++)
        if (raw[t] > 0.0 && R_ID(idx[t]) == id &&
            (same_surface(z0, R_DEPTH(idx[t])) || round_trip(there, back_off + idx[t]))) {
            l.mask |= 1u << t;
            kept += raw[t];
        }
    if (kept < MID_LINK_MIN_WEIGHT)
        l.mask = 0u; // occluded or disoccluded
    return l;
}

// The tap of a link with the largest weight (lowest index on ties), or -1.
int heaviest_tap(mid_link l)
{
    if (l.mask == 0u)
        return -1;
    mid_taps t = mid_link_taps(l);
    float wt[4] = float[4](t.w00, t.w10, t.w01, t.w11);
    int best = -1;
    for (int k = 0; k < 4; k++)
        if ((l.mask & (1u << uint(k))) != 0u && (best < 0 || wt[k] > wt[best]))
            best = k;
    uint idx[4] = uint[4](l.base, l.base + 1u, l.base + pc.nx, l.base + pc.nx + 1u);
    return int(idx[best]);
}

float link_gather_g(mid_link l)
{
    return l.mask == 0u ? 0.0 : R_LINK_GATHER(l, R_G);
}

float link_gather_h(mid_link l)
{
    return l.mask == 0u ? 0.0 : R_LINK_GATHER(l, R_H);
}

void main()
{
    element_init();
    if (!inside)
        return;
    uint i = ei, k = ek, p = ey * pc.nx + ex;
    if (OP == MID_OP_GATHER || OP == MID_OP_PREPARE) {
        if (OP == MID_OP_GATHER) {
            // Keyframe k of the window is ring slot store_first + k.
            uint base = ((pc.store_first + k) % pc.store_cap) * MID_STORE_FLOATS * pc.ns;
            G(i) = store[base + MID_STORE_G * pc.ns + p];
            H(i) = store[base + MID_STORE_H * pc.ns + p];
            DEPTH(i) = store[base + MID_STORE_DEPTH * pc.ns + p];
            ID(i) = store[base + MID_STORE_ID * pc.ns + p];
            flow[i] = vec2(store[base + MID_STORE_FLOW_F * pc.ns + 2u * p], store[base + MID_STORE_FLOW_F * pc.ns + 2u * p + 1u]);
            flow[pc.cap + i] = vec2(store[base + MID_STORE_FLOW_B * pc.ns + 2u * p], store[base + MID_STORE_FLOW_B * pc.ns + 2u * p + 1u]);
            if (p == 0u) {
                INVDT_F(k) = k + 1u < pc.nt ? 1.0 / pc.dt : 0.0;
                INVDT_B(k) = k > 0u ? 1.0 / pc.dt : 0.0;
            }
        }
        cursor[i] = 0u;
        cursor[pc.cap + i] = 0u;
        if (pc.range_hull != 0u) {
            // The range of g (operator none keeps g: its box must hold it).
            atomicMin(st.g_min_bits, floatBitsToUint(G(i)));
            atomicMax(st.g_max_bits, floatBitsToUint(G(i)));
        }
    } else if (OP == MID_OP_LINKS) {
        for (uint dir = 0u; dir < 2u; dir++) {
            mid_link l = link_make(i, int(ex), int(ey), int(k), dir);
            link[dir * pc.cap + i] = l;
            uint idx[4] = uint[4](l.base, l.base + 1u, l.base + pc.nx, l.base + pc.nx + 1u);
            for (uint t = 0u; t < 4u; t++)
                if ((l.mask & (1u << t)) != 0u)
                    atomicAdd(cursor[dir * pc.cap + idx[t]], 1u);
        }
    } else if (OP == MID_OP_FILL) {
        for (uint dir = 0u; dir < 2u; dir++) {
            mid_link l = r_link(dir * pc.cap + i);
            if (l.mask == 0u)
                continue;
            mid_taps tw = mid_link_taps(l);
            float wt[4] = float[4](tw.w00, tw.w10, tw.w01, tw.w11);
            uint idx[4] = uint[4](l.base, l.base + 1u, l.base + pc.nx, l.base + pc.nx + 1u);
            for (uint t = 0u; t < 4u; t++)
                if ((l.mask & (1u << t)) != 0u) {
                    uint slot = atomicAdd(cursor[dir * pc.cap + idx[t]], 1u);
                    mid_adj_entry e;
                    e.src = i;
                    e.w = wt[t];
                    adj[dir * pc.adj_cap + R_ADJ_OFF(dir, idx[t]) + slot] = e;
                }
        }
    } else if (OP == MID_OP_SORT) {
        // Atomics filled each row in any order; the CPU's is by source.
        for (uint dir = 0u; dir < 2u; dir++) {
            uint a = dir * pc.adj_cap + adj_off[dir * (pc.cap + 1u) + i];
            uint b = dir * pc.adj_cap + adj_off[dir * (pc.cap + 1u) + i + 1u];
            for (uint q = a + 1u; q < b; q++) {
                mid_adj_entry e = adj[q];
                uint r = q;
                while (r > a && adj[r - 1u].src > e.src) {
                    adj[r] = adj[r - 1u];
                    r--;
                }
                adj[r] = e;
            }
        }
    } else if (OP == MID_OP_TARGETS) {
        // Sec. 4.1: a = exp(-10 |dh|), h normalised over the target range;
        // c_s uses a^2 per edge.
        float hi = R_H(i);
        float ax = ex + 1u < pc.nx ? mid_edge_weight((R_H(i + 1u) - hi) * st.inv_range) : 0.0;
        float ay = ey + 1u < pc.ny ? mid_edge_weight((R_H(i + pc.nx) - hi) * st.inv_range) : 0.0;
        EDGE_X(i) = ax * ax;
        EDGE_Y(i) = ay * ay;
        mid_link lf = r_link(i), lb = r_link(pc.cap + i);
        float mf = lf.mask != 0u ? 1.0 : 0.0, mb = lb.mask != 0u ? 1.0 : 0.0;
        float idf = R_INVDT_F(k), idb = R_INVDT_B(k);
        float ha = link_gather_h(lf), ga = link_gather_g(lf), gb = link_gather_g(lb), gi = R_G(i);
        PH(i) = mf * mid_p((ha - hi) * idf);
        PG(i) = mf * mb * (mid_p((ga - gi) * idf) - mid_p((gi - gb) * idb));
        heavy[i] = heaviest_tap(lf);
        heavy[pc.cap + i] = heaviest_tap(lb);
        CHAIN_NEXT(i) = -1;
        CHAIN_PREV(i) = -1;
    } else if (OP == MID_OP_CHAINS) {
        // Mutual heaviest taps make disjoint chains along the flow.
        int j = R_HEAVY(i);
        if (j >= 0 && R_HEAVY(pc.cap + uint(j)) == int(i)) {
            CHAIN_NEXT(i) = j;
            CHAIN_PREV(uint(j)) = int(i);
        }
    } else if (OP == MID_OP_HEADS) {
        // The heads the line preconditioner walks from, so its walks run
        // over heads only (any order: the chains are disjoint).
        if (R_CHAIN_PREV(i) < 0)
            heads[atomicAdd(st.heads, 1u)] = i;
    }
}
