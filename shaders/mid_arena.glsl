// vergence — the solver arena of the mid.* passes: every array at the fixed
// binding mid_shared.h names (MID_B_*), the push constants, and the element
// grid. One dispatch per frame graph pass: the graph derives the barriers
// between them. Element kernels run one coarse pixel per invocation over a
// (x, y, keyframe) grid of MID_TILE x MID_TILE workgroups: no integer
// division and no barrier (both are slow on a CPU rasteriser); their sums
// go to per-element terms (dot) that mid_sum.comp adds in fixed chunks.
#extension GL_EXT_scalar_block_layout : require
#include "disparity/mid_shared.h"

layout(push_constant, scalar) uniform Push { mid_push pc; };

layout(set = 0, binding = MID_B_STATE, scalar) buffer StateBlock { mid_solve_state st; };
layout(set = 0, binding = MID_B_ARGS) buffer ArgsBlock { uint args[]; };
layout(set = 0, binding = MID_B_PARTIAL) buffer PartialBlock { float partial[]; };
layout(set = 0, binding = MID_B_FIELD) buffer FieldBlock { float field[]; };
layout(set = 0, binding = MID_B_FLOW, scalar) buffer FlowBlock { vec2 flow[]; };
layout(set = 0, binding = MID_B_LINK, scalar) buffer LinkBlock { mid_link link[]; };
layout(set = 0, binding = MID_B_ADJ_OFF) buffer AdjOffBlock { uint adj_off[]; };
layout(set = 0, binding = MID_B_ADJ, scalar) buffer AdjBlock { mid_adj_entry adj[]; };
layout(set = 0, binding = MID_B_CURSOR) buffer CursorBlock { uint cursor[]; };
layout(set = 0, binding = MID_B_EDGE) buffer EdgeBlock { float edge[]; };
layout(set = 0, binding = MID_B_TARGET) buffer TargetBlock { float target[]; };
layout(set = 0, binding = MID_B_INVDT) buffer InvDtBlock { float invdt[]; };
layout(set = 0, binding = MID_B_CHAIN) buffer ChainBlock { int chain[]; };
layout(set = 0, binding = MID_B_HEAVY) buffer HeavyBlock { int heavy[]; };
layout(set = 0, binding = MID_B_SCAN) buffer ScanBlock { uint scan[]; };
layout(set = 0, binding = MID_B_F) buffer FBlock { float vf[]; };
layout(set = 0, binding = MID_B_FTRY) buffer FTryBlock { float vftry[]; };
layout(set = 0, binding = MID_B_GRAD) buffer GradBlock { float vgrad[]; };
layout(set = 0, binding = MID_B_DIAG) buffer DiagBlock { float vdiag[]; };
layout(set = 0, binding = MID_B_S) buffer SBlock { float vs[]; };
layout(set = 0, binding = MID_B_R) buffer RBlock { float vr[]; };
layout(set = 0, binding = MID_B_Z) buffer ZBlock { float vz[]; };
layout(set = 0, binding = MID_B_P) buffer PBlock { float vp[]; };
layout(set = 0, binding = MID_B_HP) buffer HpBlock { float vhp[]; };
layout(set = 0, binding = MID_B_FREE) buffer FreeBlock { float vfree[]; };
layout(set = 0, binding = MID_B_L) buffer LBlock { float vl[]; };
layout(set = 0, binding = MID_B_LIN) buffer LinBlock { float lin[]; };
layout(set = 0, binding = MID_B_FPREV) buffer FPrevBlock { float fprev[]; };
layout(set = 0, binding = MID_B_STORE) buffer StoreBlock { float store[]; };
layout(set = 0, binding = MID_B_PUBLISHED, scalar) buffer PublishedBlock { mid_published pub; float pub_ratio[]; };
layout(set = 0, binding = MID_B_DOT) buffer DotBlock { float dot_terms[]; };
layout(set = 0, binding = MID_B_HEADS) buffer HeadsBlock { uint heads[]; };

// The same arena read through two texel views (set 1): a CPU rasteriser
// loads a storage buffer lane by lane in a loop, a texel fetch as one gather
// (llvmpipe: a quarter of the instructions; docs/PERFORMANCE.md). The R_*
// forms below read an array through them; a kernel uses them only for what
// no invocation of its own dispatch writes (a texel cache need not see
// those writes), and the storage buffer names above for everything else.
// W_*: each array's first 32-bit word in the arena, specialisation
// constants 1 + MID_B_* that solve_gpu.c fills in.
layout(set = 1, binding = 0) uniform usamplerBuffer arena_u;  // R32_UINT
layout(set = 1, binding = 1) uniform usamplerBuffer arena_u4; // R32G32B32A32_UINT
layout(constant_id = 1 + MID_B_FIELD) const uint W_FIELD = 0u;
layout(constant_id = 1 + MID_B_FLOW) const uint W_FLOW = 0u;
layout(constant_id = 1 + MID_B_LINK) const uint W_LINK = 0u;
layout(constant_id = 1 + MID_B_ADJ_OFF) const uint W_ADJ_OFF = 0u;
layout(constant_id = 1 + MID_B_ADJ) const uint W_ADJ = 0u;
layout(constant_id = 1 + MID_B_EDGE) const uint W_EDGE = 0u;
layout(constant_id = 1 + MID_B_TARGET) const uint W_TARGET = 0u;
layout(constant_id = 1 + MID_B_INVDT) const uint W_INVDT = 0u;
layout(constant_id = 1 + MID_B_CHAIN) const uint W_CHAIN = 0u;
layout(constant_id = 1 + MID_B_HEAVY) const uint W_HEAVY = 0u;
layout(constant_id = 1 + MID_B_F) const uint W_F = 0u;
layout(constant_id = 1 + MID_B_FTRY) const uint W_FTRY = 0u;
layout(constant_id = 1 + MID_B_GRAD) const uint W_GRAD = 0u;
layout(constant_id = 1 + MID_B_DIAG) const uint W_DIAG = 0u;
layout(constant_id = 1 + MID_B_S) const uint W_S = 0u;
layout(constant_id = 1 + MID_B_R) const uint W_R = 0u;
layout(constant_id = 1 + MID_B_Z) const uint W_Z = 0u;
layout(constant_id = 1 + MID_B_P) const uint W_P = 0u;
layout(constant_id = 1 + MID_B_HP) const uint W_HP = 0u;
layout(constant_id = 1 + MID_B_FREE) const uint W_FREE = 0u;
layout(constant_id = 1 + MID_B_L) const uint W_L = 0u;
layout(constant_id = 1 + MID_B_LIN) const uint W_LIN = 0u;
layout(constant_id = 1 + MID_B_DOT) const uint W_DOT = 0u;

uint rd_u(uint w) { return texelFetch(arena_u, int(w)).r; }
float rd_f(uint w) { return uintBitsToFloat(texelFetch(arena_u, int(w)).r); }

#define R_F(i) rd_f(W_F + (i))
#define R_FTRY(i) rd_f(W_FTRY + (i))
#define R_GRAD(i) rd_f(W_GRAD + (i))
#define R_DIAG(i) rd_f(W_DIAG + (i))
#define R_S(i) rd_f(W_S + (i))
#define R_R(i) rd_f(W_R + (i))
#define R_Z(i) rd_f(W_Z + (i))
#define R_P(i) rd_f(W_P + (i))
#define R_HP(i) rd_f(W_HP + (i))
#define R_FREE(i) rd_f(W_FREE + (i))
#define R_G(i) rd_f(W_FIELD + (i))
#define R_H(i) rd_f(W_FIELD + pc.cap + (i))
#define R_DEPTH(i) rd_f(W_FIELD + 2u * pc.cap + (i))
#define R_ID(i) rd_f(W_FIELD + 3u * pc.cap + (i))
#define R_FLOW(i) vec2(rd_f(W_FLOW + 2u * (i)), rd_f(W_FLOW + 2u * (i) + 1u))
#define R_INVDT_F(k) rd_f(W_INVDT + (k))
#define R_INVDT_B(k) rd_f(W_INVDT + MID_MAX_KEYFRAMES + (k))
#define R_HEAVY(i) int(rd_u(W_HEAVY + (i)))
#define R_EDGE_X(i) rd_f(W_EDGE + (i))
#define R_EDGE_Y(i) rd_f(W_EDGE + pc.cap + (i))
#define R_PH(i) rd_f(W_TARGET + (i))
#define R_PG(i) rd_f(W_TARGET + pc.cap + (i))
#define R_CHAIN_NEXT(i) int(rd_u(W_CHAIN + (i)))
#define R_CHAIN_PREV(i) int(rd_u(W_CHAIN + pc.cap + (i)))
#define R_L0(i) rd_f(W_L + (i))
#define R_L1(i) rd_f(W_L + pc.cap + (i))
#define R_L2(i) rd_f(W_L + 2u * pc.cap + (i))
#define R_Q_F(i) rd_f(W_LIN + (i))
#define R_Q_B(i) rd_f(W_LIN + pc.cap + (i))
#define R_M_A(i) rd_f(W_LIN + 2u * pc.cap + (i))
#define R_ALPHA(i) rd_f(W_LIN + 3u * pc.cap + (i))
#define R_BETA(i) rd_f(W_LIN + 4u * pc.cap + (i))
#define R_C_F(i) rd_f(W_LIN + 5u * pc.cap + (i))
#define R_C_B(i) rd_f(W_LIN + 6u * pc.cap + (i))
#define R_D_SELF(i) rd_f(W_LIN + 7u * pc.cap + (i))
#define R_DOT(c, i) rd_f(W_DOT + (c) * pc.cap + (i))
// CSR rows of A_f^T (dir 0) and A_b^T (dir 1): row j's entries are
// [R_ADJ_OFF(dir, j), R_ADJ_OFF(dir, j + 1)); entry q's source and weight.
#define R_ADJ_OFF(dir, j) rd_u(W_ADJ_OFF + (dir) * (pc.cap + 1u) + (j))
#define R_ADJ_SRC(dir, q) rd_u(W_ADJ + 2u * ((dir) * pc.adj_cap + (q)))
#define R_ADJ_W(dir, q) rd_f(W_ADJ + 2u * ((dir) * pc.adj_cap + (q)) + 1u)

// Link i of A_f (i < cap) or A_b (cap + i): one 16-byte texel.
mid_link r_link(uint i)
{
    uvec4 v = texelFetch(arena_u4, int(W_LINK / 4u + i));
    mid_link l;
    l.base = v.x;
    l.fx = uintBitsToFloat(v.y);
    l.fy = uintBitsToFloat(v.z);
    l.mask = v.w;
    return l;
}

// Arrays of several fields, each cap long (mid_shared.h).
#define G(i) field[(i)]
#define H(i) field[pc.cap + (i)]
#define DEPTH(i) field[2u * pc.cap + (i)]
#define ID(i) field[3u * pc.cap + (i)]
#define EDGE_X(i) edge[(i)]
#define EDGE_Y(i) edge[pc.cap + (i)]
#define PH(i) target[(i)]
#define PG(i) target[pc.cap + (i)]
#define INVDT_F(k) invdt[(k)]
#define INVDT_B(k) invdt[MID_MAX_KEYFRAMES + (k)]
#define CHAIN_NEXT(i) chain[(i)]
#define CHAIN_PREV(i) chain[pc.cap + (i)]
#define L0(i) vl[(i)]
#define L1(i) vl[pc.cap + (i)]
#define L2(i) vl[2u * pc.cap + (i)]
#define Q_F(i) lin[(i)]
#define Q_B(i) lin[pc.cap + (i)]
#define M_A(i) lin[2u * pc.cap + (i)]
#define ALPHA(i) lin[3u * pc.cap + (i)]
#define BETA(i) lin[4u * pc.cap + (i)]
#define C_F(i) lin[5u * pc.cap + (i)]
#define C_B(i) lin[6u * pc.cap + (i)]
#define D_SELF(i) lin[7u * pc.cap + (i)]

// (A x)_i of a link, x read by R (through the texel views: an array no invocation of the
// dispatch writes); taps outside the mask have weight 0 and a valid index.
#define R_LINK_GATHER(l, R)                                                                \
    mid_link_apply(mid_link_taps(l), R((l).base), R((l).base + 1u), R((l).base + pc.nx),  \
                   R((l).base + pc.nx + 1u))

// Per-element terms of the sums (column c of MID_DOT_COLUMNS).
#define DOT(c, i) dot_terms[(c) * pc.cap + (i)]

// The element of this invocation: coarse pixel (ex, ey) of keyframe ek,
// index ei = (ek ny + ey) nx + ex; `inside` is false past the grid's edge.
#define MID_ELEMENT_LAYOUT layout(local_size_x = MID_TILE, local_size_y = MID_TILE) in
uint ex, ey, ek, ei;
bool inside;

void element_init()
{
    ex = gl_GlobalInvocationID.x;
    ey = gl_GlobalInvocationID.y;
    ek = gl_GlobalInvocationID.z;
    inside = ex < pc.nx && ey < pc.ny && ek < pc.nt;
    ei = (ek * pc.ny + ey) * pc.nx + ex;
}
