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

// (A x)_i of a link over one of the arrays (dir 0: A_f, 1: A_b); taps
// outside the mask have weight 0 and a valid index.
#define LINK_GATHER(l, arr, off)                                                          \
    mid_link_apply(mid_link_taps(l), arr[(off) + (l).base], arr[(off) + (l).base + 1u],    \
                   arr[(off) + (l).base + pc.nx], arr[(off) + (l).base + pc.nx + 1u])

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
