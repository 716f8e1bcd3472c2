// The flight of one particle per invocation through the steps of one layer epoch (or part of
// one), against the layers as they stood at the epoch's start: the GPU twin of the engine's
// `pipeline/kernel.rs`, in f32, with every surface tested in every step. A dispatch covers
// every member of a batch (one simulation's call each, with its own parameters, scene, layers
// and counters; one member for a single run). A call dispatches `restore` (the layers as the
// call finds them), `born` (its newborns, `births.wgsl`), then, per epoch, `fly` (its steps in
// the parameters at the epoch's dynamic offset), `census`, `settle` (the layers brought up to
// date with what the call has deposited so far) and `census` again, and `gather` to end. `census`
// copies the few counters that many invocations read into plain words (`plan`): an atomic load
// of one word by every invocation is serialised, and would cost more than the flight. It also
// writes the size of `settle`'s and `gather`'s dispatches (`listed_groups`), which cover only
// the cells listed.
//
// Layouts (word offsets, all u32; f32 through bitcast) are written by `pack.rs`, whose
// constants these mirror. What a particle leaves behind is booked in integer atomics, whose
// sums do not depend on the order of the invocations: volumes in quanta as 64-bit pairs
// (low word, high word, the carry added by whoever wraps the low word).

// The parameters of a call's epoch, for every member of the batch.
struct Params {
    steps: vec4<u32>,      // from, to, particle slots of all members, invocations per dispatch row
    sizes: vec4<u32>,      // members, targets of all members, cells of all grids, whether any target erodes
}

// One member of the batch (one simulation's call), as `load_member` reads it from its
// MEMBER_WORDS words at the start of `scene`.
struct Member {
    gravity_dt: vec4<f32>, // g (m/s²), Δt (s)
    min_drag: vec4<f32>,   // domain min (m), quadratic drag k (1/m)
    max_life: vec4<f32>,   // domain max (m), lifetime in steps
    run: vec4<u32>,        // integrator (0 Euler, 1 semi-implicit, 2 exact), seed low, seed high, impacts per step
    sizes: vec4<u32>,      // targets, obstacle shapes, released particles, a nozzle particle's quanta
    tables: vec4<u32>,     // word offsets of its own words (its models first), targets, shapes, released table
    place: vec4<u32>,      // its first particle slot, first target over all members, first cell, counter words
    births: vec4<u32>,     // offset of its emitter's words (its batches of births after them), batches, slots of its swarm, newborns
}

// 36 bytes a slot: position (m), velocity (m/s), birth step, id, impacts (low 12 bits) and
// status bits (the next 4).
struct Particle {
    x: f32, y: f32, z: f32,
    vx: f32, vy: f32, vz: f32,
    born: u32,
    id: u32,
    status: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> particles: array<Particle>;
@group(0) @binding(2) var<storage, read> scene: array<u32>;
// The layers, m, every target's cells one after the other (and a spare): first as the epoch
// under way sees them, then, from word `cells + 1`, as the call found them.
@group(0) @binding(3) var<storage, read_write> thickness: array<f32>;
@group(0) @binding(4) var<storage, read_write> counters: array<atomic<u32>>;
// Per cell of every grid: deposit quanta (low, high), impacts, and a mark (listed this call).
@group(0) @binding(5) var<storage, read_write> cells: array<atomic<u32>>;
// The cells listed, 4 words each: the cell (over all grids), then, after `gather`, its
// deposit quanta (low, high) and impacts.
@group(0) @binding(6) var<storage, read_write> listed: array<u32>;
// As the last `census` found them: [0] the cells listed, then each target's band (f32 bits).
@group(0) @binding(7) var<storage, read_write> plan: array<u32>;
// Where a target erodes, per cell of every grid: the coating's and the substrate's wear in
// WEAR_QUANTUMs (2⁻⁹⁰ m³), each as (low, high); from word 4 × (cells + 1), after `gather`, the
// same for each listed cell. A spare word where nothing erodes.
@group(0) @binding(8) var<storage, read_write> wear: array<atomic<u32>>;
// The size of the dispatches over the listed cells (`settle`, `gather`), as the last `census`
// counted them: workgroups across, rows, 1. Bound for `census` alone (in a group of its own,
// with the bindings it reads), which writes it; the others' dispatches read it as their size.
@group(0) @binding(9) var<storage, read_write> listed_groups: array<u32>;

// The member the invocation flies a particle of.
var<private> M: Member;

const MEMBER_WORDS: u32 = 32u;
// Words of each target in the table of all members' targets (after the members' words): its
// first cell over all grids, a quantum's thickness on one of its cells (f32 bits), the counter
// word that holds its band, and a spare.
const TABLE_WORDS: u32 = 4u;

const ALIVE: u32 = 1u;
const HIT_SUBSTRATE: u32 = 2u;
const RELEASED: u32 = 4u;
const BOUNCED: u32 = 8u;
const MAX_IMPACTS: u32 = 4095u;
const MATERIAL_EVENT: u32 = 0xffffffffu;
// A rebound leaves from this far off the surface struck (m): above f32's resolution of
// coordinates of a few metres (0.5 µm at 4 m).
const SURFACE_OFFSET: f32 = 2e-6;

// Model words (per owner: the targets, then the obstacles).
const MODEL_WORDS: u32 = 64u;
// Target words: its surface (a rectangle's centre, normal, up, right; a shell's centre, axis,
// e1, e2), the half width and height of its grid, cols, rows, its first cell over all grids, the
// band at the call's start, substrate or not, the footprint's offsets and count, a quantum's
// thickness on one cell, its openings' polygons, count and hole bits, its erosion's words, and
// for a shell its radius, the side sprayed, its start angle and whether its grid wraps; its
// kind (see `pack.rs`).
const TARGET_WORDS: u32 = 32u;
// Kinds of target (word 29).
const RECTANGLE: u32 = 0u;
const SHELL: u32 = 1u;
// Words of one erosion law.
const LAW_WORDS: u32 = 8u;
// Shape words: its kind, its obstacle, its geometry (words 2 to 15), then its bounding box from
// word 16 (BOX_WORDS: lower corner and a spare, upper corner and a spare, m; ±f32's largest
// where unbounded). The member's shapes' table begins with the box around all of them.
const SHAPE_WORDS: u32 = 24u;
const BOX_WORDS: u32 = 8u;

// Counters: [0] the cells listed (of all members), three spare words, then each member's from
// its `place.w`: [0, 1] particle-steps (low, high), two spare words, then its fates (slots of
// 4 words: count, quanta low, quanta high, unused), then per target and per obstacle. The
// fourth word of a target's first slot holds the band its layer may fill (f32 bits, m: at least
// its thickest cell's thickness, raised by `settle`).
const C_LISTED: u32 = 0u;
const C_STEPS: u32 = 0u;
const C_TALLY: u32 = 4u;
const T_LEFT: u32 = 0u;
const T_EXPIRED: u32 = 1u;
const T_OVERSPRAY: u32 = 2u;
const T_FIRST: u32 = 3u;
const T_FIRST_REBOUND: u32 = 4u;
const T_RELEASED_LEFT: u32 = 5u;
const T_RELEASED_EXPIRED: u32 = 6u;
const TALLY_SLOTS: u32 = 7u;
// Per target: hits, stuck, loose, trapped, delivered, stuck on the back, received, received on
// the back.
const TG_HITS: u32 = 0u;
const TG_STUCK: u32 = 1u;
const TG_LOOSE: u32 = 2u;
const TG_TRAPPED: u32 = 3u;
const TG_DELIVERED: u32 = 4u;
const TG_STUCK_BACK: u32 = 5u;
const TG_RECEIVED: u32 = 6u;
const TG_RECEIVED_BACK: u32 = 7u;
const TARGET_SLOTS: u32 = 8u;
// Per obstacle: hits, stuck, received.
const OB_HITS: u32 = 0u;
const OB_STUCK: u32 = 1u;
const OB_RECEIVED: u32 = 2u;
const OBSTACLE_SLOTS: u32 = 3u;

fn f(at: u32) -> f32 {
    return bitcast<f32>(scene[at]);
}

fn v3(at: u32) -> vec3<f32> {
    return vec3<f32>(f(at), f(at + 1u), f(at + 2u));
}

fn u4(at: u32) -> vec4<u32> {
    return vec4<u32>(scene[at], scene[at + 1u], scene[at + 2u], scene[at + 3u]);
}

fn f4(at: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(u4(at));
}

// Reads member m into `M`.
fn load_member(m: u32) {
    let at = MEMBER_WORDS * m;
    M = Member(
        f4(at), f4(at + 4u), f4(at + 8u), u4(at + 12u), u4(at + 16u), u4(at + 20u), u4(at + 24u), u4(at + 28u),
    );
}

// The member whose particle slots hold slot i: the last whose first slot is not past it.
fn member_of(i: u32) -> u32 {
    var lo = 0u;
    var hi = params.sizes.x;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (scene[MEMBER_WORDS * mid + 24u] <= i) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A word offset written in the member's own words (relative to their start), made absolute.
fn own(relative: u32) -> u32 {
    return M.tables.x + relative;
}

// The first cell (over all grids) of the target at `at` in the member's words.
fn first_cell(at: u32) -> u32 {
    return M.place.z + scene[at + 16u];
}

// ---- Integer books ----

fn add64(at: u32, q: vec2<u32>) {
    let old = atomicAdd(&counters[at], q.x);
    let carry = select(0u, 1u, old + q.x < old);
    if (q.y + carry != 0u) {
        atomicAdd(&counters[at + 1u], q.y + carry);
    }
}

// Counts one particle of `q` quanta in the run's fate `slot`.
fn tally(slot: u32, q: vec2<u32>) {
    count_at(M.place.w + C_TALLY + 4u * slot, q);
}

fn target_slot(t: u32, slot: u32) -> u32 {
    return M.place.w + C_TALLY + 4u * TALLY_SLOTS + 4u * (TARGET_SLOTS * t + slot);
}

// The band the member's target t's layer may fill, m: no cell of the epoch's layers is thicker.
fn band(t: u32) -> f32 {
    return bitcast<f32>(plan[1u + M.place.y + t]);
}

fn obstacle_slot(o: u32, slot: u32) -> u32 {
    return M.place.w + C_TALLY + 4u * TALLY_SLOTS + 4u * (TARGET_SLOTS * M.sizes.x + OBSTACLE_SLOTS * o + slot);
}

// Counts one particle of `q` quanta in the slot at counter word `at` (count, low, high).
fn count_at(at: u32, q: vec2<u32>) {
    atomicAdd(&counters[at], 1u);
    add64(at + 1u, q);
}

// Lists `cell` (over all grids) the first time anything lands on it in this call.
fn mark(cell: u32) {
    if (atomicExchange(&cells[4u * cell + 3u], 1u) == 0u) {
        let k = atomicAdd(&counters[C_LISTED], 1u);
        listed[4u * k] = cell;
    }
}

fn deposit(cell: u32, q: vec2<u32>) {
    if (q.x == 0u && q.y == 0u) {
        return;
    }
    let old = atomicAdd(&cells[4u * cell], q.x);
    let carry = select(0u, 1u, old + q.x < old);
    if (q.y + carry != 0u) {
        atomicAdd(&cells[4u * cell + 1u], q.y + carry);
    }
    mark(cell);
}

// Adds the 64-bit `q` to the wear counter pair at `at`.
fn add_wear(at: u32, q: vec2<u32>) {
    let old = atomicAdd(&wear[at], q.x);
    let carry = select(0u, 1u, old + q.x < old);
    if (q.y + carry != 0u) {
        atomicAdd(&wear[at + 1u], q.y + carry);
    }
}

// `q` split over `n` cells (n < 2¹⁶): share k takes q / n, and share 0 the remainder too.
fn share(q: vec2<u32>, n: u32, k: u32) -> vec2<u32> {
    let hi = q.y / n;
    let r = q.y % n;
    let t1 = (r << 16u) | (q.x >> 16u);
    let q1 = t1 / n;
    let r1 = t1 % n;
    let t2 = (r1 << 16u) | (q.x & 0xffffu);
    let q2 = t2 / n;
    let r2 = t2 % n;
    var lo = (q1 << 16u) | q2;
    var out_hi = hi;
    if (k == 0u) {
        let sum = lo + r2;
        out_hi += select(0u, 1u, sum < lo);
        lo = sum;
    }
    return vec2<u32>(lo, out_hi);
}

// ---- Random streams: a counter-based hash of (seed, particle, event, draw) ----

fn mix32(x0: u32) -> u32 {
    var x = x0;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// A uniform draw in [0, 1) with 24 bits.
fn uniform01(id: u32, event: u32, draw: u32) -> f32 {
    var h = mix32(M.run.y ^ 0x9e3779b9u);
    h = mix32(h ^ M.run.z);
    h = mix32(h ^ id);
    h = mix32(h ^ event);
    h = mix32(h ^ (draw * 0x85ebca6bu));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// ---- Motion ----

fn acceleration(v: vec3<f32>) -> vec3<f32> {
    let g = M.gravity_dt.xyz;
    let k = M.min_drag.w;
    if (k == 0.0) {
        return g;
    }
    return g - k * length(v) * v;
}

struct State {
    x: vec3<f32>,
    v: vec3<f32>,
}

fn advance(x: vec3<f32>, v: vec3<f32>, h: f32) -> State {
    let a = acceleration(v);
    let v1 = v + a * h;
    var x1 = x + v * h;
    if (M.run.x == 1u) {
        x1 = x + v1 * h;
    } else if (M.run.x == 2u) {
        x1 = x + v * h + 0.5 * a * h * h;
    }
    return State(x1, v1);
}

// ---- Surfaces ----

// The first hit of a segment: its fraction of the segment, point, normal (facing the side the
// segment came from), the owner (target t, or obstacle `OBSTACLE + o`), and on a target's front
// the cell struck (else `NO_CELL`).
struct Hit {
    t: f32,
    point: vec3<f32>,
    normal: vec3<f32>,
    owner: u32,
    cell: u32,
}

const NONE: f32 = 2.0;
const OBSTACLE: u32 = 0x10000u;
const NO_CELL: u32 = 0xffffffffu;
const NO_SLOT: u32 = 0xffffffffu;

fn no_hit() -> Hit {
    return Hit(NONE, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), 0u, NO_CELL);
}

// The smaller root in [0, 1] of a t² + 2 b t + c = 0 entered from outside (c ≥ 0), or NONE.
fn entry_root(a: f32, b: f32, c: f32) -> f32 {
    if (a <= 0.0 || b >= 0.0) {
        return NONE;
    }
    let disc = b * b - a * c;
    if (disc < 0.0) {
        return NONE;
    }
    let t = (-b - sqrt(disc)) / a;
    if (t < 0.0 || t > 1.0) {
        return NONE;
    }
    return t;
}

// A plane's crossing by the segment: (fraction, signed distance at its start), or NONE.
fn crossing(point: vec3<f32>, n: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>) -> vec2<f32> {
    let d0 = dot(p0 - point, n);
    let d1 = dot(p1 - point, n);
    if ((d0 > 0.0 && d1 <= 0.0) || (d0 < 0.0 && d1 >= 0.0)) {
        return vec2<f32>(clamp(d0 / (d0 - d1), 0.0, 1.0), d0);
    }
    return vec2<f32>(NONE, 0.0);
}

fn facing(n: vec3<f32>, d0: f32) -> vec3<f32> {
    return select(-n, n, d0 > 0.0);
}

fn shape_hit(at: u32, p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    var h = no_hit();
    let kind = scene[at];
    let d = p1 - p0;
    switch kind {
        // Plane: point, normal.
        case 0u: {
            let c = crossing(v3(at + 2u), v3(at + 5u), p0, p1);
            if (c.x <= 1.0) {
                h = Hit(c.x, p0 + d * c.x, facing(v3(at + 5u), c.y), 0u, NO_CELL);
            }
        }
        // Sphere: centre, radius.
        case 1u: {
            let m = p0 - v3(at + 2u);
            let r = f(at + 5u);
            let c = dot(m, m) - r * r;
            if (c < 0.0) {
                h = Hit(0.0, p0, normalize(m), 0u, NO_CELL);
            } else {
                let t = entry_root(dot(d, d), dot(m, d), c);
                if (t <= 1.0) {
                    let q = p0 + d * t;
                    h = Hit(t, q, normalize(q - v3(at + 2u)), 0u, NO_CELL);
                }
            }
        }
        // Cylinder: cap centres a, b, radius.
        case 2u: {
            h = cylinder_hit(v3(at + 2u), v3(at + 5u), f(at + 8u), p0, p1);
        }
        // Disk: centre, normal, radius.
        case 3u: {
            let c = crossing(v3(at + 2u), v3(at + 5u), p0, p1);
            if (c.x <= 1.0) {
                let q = p0 + d * c.x;
                let r = f(at + 8u);
                let off = q - v3(at + 2u);
                if (dot(off, off) <= r * r) {
                    h = Hit(c.x, q, facing(v3(at + 5u), c.y), 0u, NO_CELL);
                }
            }
        }
        // Box: centre, two of its local axes (the third is their cross product), half extents.
        case 5u: {
            h = box_hit(at, p0, p1);
        }
        // Face: centre, normal, up, right, half width, half height.
        default: {
            let c = crossing(v3(at + 2u), v3(at + 5u), p0, p1);
            if (c.x <= 1.0) {
                let q = p0 + d * c.x;
                let off = q - v3(at + 2u);
                if (abs(dot(off, v3(at + 11u))) <= f(at + 14u) && abs(dot(off, v3(at + 8u))) <= f(at + 15u)) {
                    h = Hit(c.x, q, facing(v3(at + 5u), c.y), 0u, NO_CELL);
                }
            }
        }
    }
    h.owner = OBSTACLE + scene[at + 1u];
    return h;
}

// The first hit of the segment on the box at `at` (slab method): entering through the face on
// the side it comes from, or, starting inside, pushed out through the nearest face at once (as
// the engine's `OrientedBox`).
fn box_hit(at: u32, p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    let a0 = v3(at + 5u);
    let a1 = v3(at + 8u);
    var axes = array<vec3<f32>, 3>(a0, a1, cross(a0, a1));
    let half = v3(at + 11u);
    let rel = p0 - v3(at + 2u);
    let d = p1 - p0;
    var t_enter = -3.0e38;
    var t_exit = 3.0e38;
    var enter = vec3<f32>(0.0);
    var inside = true;
    var nearest = vec3<f32>(0.0);
    var gap = 3.0e38;
    for (var i = 0u; i < 3u; i++) {
        let o = dot(rel, axes[i]);
        let v = dot(d, axes[i]);
        let e = half[i];
        if (abs(o) >= e) {
            inside = false;
        }
        if (e - abs(o) < gap) {
            gap = e - abs(o);
            nearest = axes[i] * select(-1.0, 1.0, o >= 0.0);
        }
        if (v == 0.0) {
            if (abs(o) > e) {
                return no_hit();
            }
            continue;
        }
        var t0 = (-e - o) / v;
        var t1 = (e - o) / v;
        var side = -1.0;
        if (t0 > t1) {
            let t = t0;
            t0 = t1;
            t1 = t;
            side = 1.0;
        }
        if (t0 > t_enter) {
            t_enter = t0;
            enter = axes[i] * side;
        }
        t_exit = min(t_exit, t1);
    }
    if (inside) {
        return Hit(0.0, p0, nearest, 0u, NO_CELL);
    }
    if (t_enter > t_exit || t_enter < 0.0 || t_enter > 1.0) {
        return no_hit();
    }
    return Hit(t_enter, p0 + d * t_enter, enter, 0u, NO_CELL);
}

fn cylinder_hit(a: vec3<f32>, b: vec3<f32>, r: f32, p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    let axis = b - a;
    let len = length(axis);
    let u = axis / len;
    let m = p0 - a;
    let d = p1 - p0;
    let ms = dot(m, u);
    let ds = dot(d, u);
    let m_perp = m - u * ms;
    let d_perp = d - u * ds;
    let c = dot(m_perp, m_perp) - r * r;
    if (c < 0.0 && ms > 0.0 && ms < len) {
        // Inside: out through the nearest of mantle and caps.
        let to_mantle = r - length(m_perp);
        var n = u;
        if (to_mantle <= min(ms, len - ms)) {
            n = normalize(m_perp);
        } else if (ms < len - ms) {
            n = -u;
        }
        return Hit(0.0, p0, n, 0u, NO_CELL);
    }
    var best = no_hit();
    if (c >= 0.0) {
        let t = entry_root(dot(d_perp, d_perp), dot(m_perp, d_perp), c);
        if (t <= 1.0) {
            let s = ms + ds * t;
            if (s >= 0.0 && s <= len) {
                best = Hit(t, p0 + d * t, normalize(m_perp + d_perp * t), 0u, NO_CELL);
            }
        }
    }
    // The caps, entered from outside along the axis.
    for (var k = 0u; k < 2u; k++) {
        let cap = select(len, 0.0, k == 0u);
        let outside = select(ms > len, ms < 0.0, k == 0u);
        if (!outside || ds == 0.0) {
            continue;
        }
        let t = (cap - ms) / ds;
        if (t >= 0.0 && t <= 1.0 && t < best.t) {
            let radial = m_perp + d_perp * t;
            if (dot(radial, radial) <= r * r) {
                best = Hit(t, p0 + d * t, select(u, -u, k == 0u), 0u, NO_CELL);
            }
        }
    }
    return best;
}

// In-face coordinates of `q` on the target at `at`: m from its centre along its right and up.
fn face_uv(at: u32, q: vec3<f32>) -> vec2<f32> {
    let off = q - v3(at);
    return vec2<f32>(dot(off, v3(at + 9u)), dot(off, v3(at + 6u)));
}

// A target's grid: the cell of in-face coordinates (u, v) (m from its centre), clamped to it.
fn cell_at(at: u32, u: f32, v: f32) -> u32 {
    let cols = scene[at + 14u];
    let rows = scene[at + 15u];
    let w = 2.0 * f(at + 12u);
    let h = 2.0 * f(at + 13u);
    let col = min(u32(max((u / w + 0.5) * f32(cols), 0.0)), cols - 1u);
    let row = min(u32(max((v / h + 0.5) * f32(rows), 0.0)), rows - 1u);
    return row * cols + col;
}

// Column `c` of the target at `at`'s grid, wrapped round a shell's full turn; -1 off the grid.
fn column(at: u32, c: i32) -> i32 {
    let cols = i32(scene[at + 14u]);
    if (c >= 0 && c < cols) {
        return c;
    }
    if (scene[at + 31u] != 0u) {
        return ((c % cols) + cols) % cols;
    }
    return -1;
}

// True if the in-face point uv (m from the centre) lies in one of the openings of the target at
// `at`: the even–odd rule over each polygon, as the engine's `Opening::contains`.
fn in_opening(at: u32, uv: vec2<f32>) -> bool {
    var w = own(scene[at + 22u]);
    for (var o = 0u; o < scene[at + 23u]; o++) {
        let n = scene[w];
        var inside = false;
        for (var i = 0u; i < n; i++) {
            let j = select(i + 1u, 0u, i + 1u == n);
            let a = vec2<f32>(f(w + 1u + 2u * i), f(w + 2u + 2u * i));
            let b = vec2<f32>(f(w + 1u + 2u * j), f(w + 2u + 2u * j));
            if ((a.y > uv.y) != (b.y > uv.y) && uv.x < a.x + (uv.y - a.y) * (b.x - a.x) / (b.y - a.y)) {
                inside = !inside;
            }
        }
        if (inside) {
            return true;
        }
        w += 1u + 2u * n;
    }
    return false;
}

// True if the cell (of the target at `at`) is cut away: its centre lies in an opening.
fn is_hole(at: u32, cell: u32) -> bool {
    let bits = scene[at + 24u];
    return bits != 0u && (scene[own(bits) + cell / 32u] & (1u << (cell % 32u))) != 0u;
}

// The cell a point uv (m from the centre) on the surface near an opening's edge is booked to:
// `cell`, the one under it, unless it is cut away; then, as the engine's `GridSurface::solid`,
// the solid cell whose centre is nearest uv in the first ring of cells round `cell` that holds
// any (the lower index on a tie).
fn solid(at: u32, cell: u32, uv: vec2<f32>) -> u32 {
    if (!is_hole(at, cell)) {
        return cell;
    }
    let cols = i32(scene[at + 14u]);
    let rows = i32(scene[at + 15u]);
    let size = vec2<f32>(2.0 * f(at + 12u) / f32(cols), 2.0 * f(at + 13u) / f32(rows));
    let r0 = i32(cell) / cols;
    let c0 = i32(cell) % cols;
    for (var reach = 1; reach < max(cols, rows); reach++) {
        var best = NO_CELL;
        var nearest = 0.0;
        for (var r = max(r0 - reach, 0); r <= min(r0 + reach, rows - 1); r++) {
            for (var c = max(c0 - reach, 0); c <= min(c0 + reach, cols - 1); c++) {
                let k = u32(r * cols + c);
                if (max(abs(r - r0), abs(c - c0)) != reach || is_hole(at, k)) {
                    continue;
                }
                let centre = (vec2<f32>(f32(c), f32(r)) + 0.5) * size - vec2<f32>(f(at + 12u), f(at + 13u));
                let d = distance(centre, uv);
                // Visited in ascending index: a tie keeps the lower.
                if (best == NO_CELL || d < nearest) {
                    best = k;
                    nearest = d;
                }
            }
        }
        if (best != NO_CELL) {
            return best;
        }
    }
    return cell;
}

// The unit normal of the bare surface of the target at `at` at `q`, towards the side sprayed.
fn bare_normal(at: u32, q: vec3<f32>) -> vec3<f32> {
    if (scene[at + 29u] == SHELL) {
        return shell_normal(at, q);
    }
    return v3(at + 3u);
}

// The layer's thickness (m) in the cell under `q` on the target at `at`, the point taken to its
// grid's nearest cell: past a shell's edge or end, its edge cell's (a path that crosses the
// layer within the shell and the bare surface past its edge in one step meets the layer).
fn layer_under(at: u32, q: vec3<f32>) -> f32 {
    if (scene[at + 29u] == SHELL) {
        return shell_layer(at, shell_local(at, q));
    }
    let uv = face_uv(at, q);
    return thickness[first_cell(at) + cell_at(at, uv.x, uv.y)];
}

// The layer's thickness (m) in the cell of the shell at `at` under the point whose local
// coordinates (`shell_local`) are `l`, its edge cell's past the shell's edges.
fn shell_layer(at: u32, l: vec4<f32>) -> f32 {
    return thickness[first_cell(at) + cell_at(at, l.x, l.y)];
}

// The first fraction of the segment at which it comes down through `level` m above the surface
// of the target at `at`, towards it from the side sprayed; NONE if it does not. `h` holds the
// heights of the segment's ends above a rectangle (along which its height is linear).
fn level_down(at: u32, p0: vec3<f32>, p1: vec3<f32>, h: vec2<f32>, level: f32) -> f32 {
    if (scene[at + 29u] == SHELL) {
        return shell_level(at, p0, p1, level, true);
    }
    if (h.y < level) {
        return (h.x - level) / (h.x - h.y);
    }
    return NONE;
}

// Where a segment that starts `h.x` m above the target's surface (on the side sprayed, over
// its layer) meets the layer: the crossing of the layer's height in the cell under it, found
// again at most three times. A path that meets a column taller than its start enters it
// through its side, and the material settles in the column it came down (as in ballistic
// deposition: stacking it on the taller one would let every column that gets ahead catch its
// neighbours' flux and grow into a needle); the contact is then taken half a cell back along
// the path (within it), over the column it came down. Returns the fraction of the segment
// (above 1: none within it) and 1 where the crossing is the bare surface's (else 0).
fn layer_crossing(at: u32, p0: vec3<f32>, p1: vec3<f32>, h: vec2<f32>) -> vec2<f32> {
    let d = p1 - p0;
    var s = min(level_down(at, p0, p1, h, 0.0), 1.0);
    let shell = scene[at + 29u] == SHELL;
    // On a shell, the height at `s`: the bare surface's, or the segment's end's.
    var hs = 0.0;
    if (shell && s == 1.0) {
        hs = shell_local(at, p1).z;
    }
    var layer = -1.0;
    var side = false;
    for (var k = 0u; k < 3u; k++) {
        let next = layer_under(at, p0 + d * s);
        // Started no higher than the column, it meets its side; on a shell, where a chord's
        // height is not linear, only if it is in the column there and did not rise above it
        // and come down through its top.
        if (h.x <= next && (!shell || (hs <= next && level_down(at, p0, p1, h, next) > 1.0))) {
            side = true;
            break;
        }
        if (next == layer) {
            break;
        }
        layer = next;
        s = level_down(at, p0, p1, h, layer);
        hs = layer;
        if (s > 1.0) {
            break;
        }
    }
    if (side) {
        let n = bare_normal(at, p0 + d * s);
        let cells = vec2<f32>(2.0 * f(at + 12u) / f32(scene[at + 14u]), 2.0 * f(at + 13u) / f32(scene[at + 15u]));
        let along = length(d - n * dot(d, n));
        s = max(s - 0.5 * min(cells.x, cells.y) / max(along, 1e-12), 0.0);
    }
    return vec2<f32>(s, select(0.0, 1.0, !side && layer <= 0.0));
}

// The first hit of the segment on target t: its layer from the front (read as flat at the
// thickness of the cell under the crossing: `layer_crossing`), or its bare back. A crossing of the bare surface inside an opening passes: a straight path that has
// crossed its plane there meets nothing more of the target.
fn target_hit(t: u32, p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    let at = M.tables.y + TARGET_WORDS * t;
    if (scene[at + 29u] == SHELL) {
        return shell_hit(t, p0, p1);
    }
    let c = v3(at);
    let n = v3(at + 3u);
    let top = band(t);
    let h0 = dot(p0 - c, n);
    let h1 = dot(p1 - c, n);
    // Neither into the band from the front nor onto the back (the cases below): most steps,
    // which need read nothing more of the target.
    if (!(h0 > 0.0 && min(h0, h1) <= top) && !(h0 < 0.0 && h1 >= 0.0)) {
        return no_hit();
    }
    let hw = f(at + 12u);
    let hh = f(at + 13u);
    let first = first_cell(at);
    let d = p1 - p0;
    var own = 0.0;
    let uv0 = face_uv(at, p0);
    if (h0 > 0.0 && h0 <= top && abs(uv0.x) <= hw && abs(uv0.y) <= hh) {
        own = thickness[first + cell_at(at, uv0.x, uv0.y)];
    }
    // The fraction of the path at which it meets the target, and on which side.
    var s = NONE;
    var front = true;
    // Whether the crossing is the bare surface's (not the top or side of a layer).
    var bare = true;
    if (h0 > 0.0 && h0 <= own) {
        // Starting inside the layer, a path enters it only after leaving it: within one step it
        // meets only the bare surface.
        if (h1 <= 0.0) {
            s = h0 / (h0 - h1);
        }
    } else if (h0 > 0.0 && h1 <= top) {
        // From the front, into the band the layer may fill.
        let crossing = layer_crossing(at, p0, p1, vec2<f32>(h0, h1));
        s = crossing.x;
        bare = crossing.y > 0.0;
    } else if (h0 < 0.0 && h1 >= 0.0) {
        // From behind, onto the bare back.
        s = clamp(h0 / (h0 - h1), 0.0, 1.0);
        front = false;
    }
    if (s > 1.0) {
        return no_hit();
    }
    let q = p0 + d * s;
    let uv = face_uv(at, q);
    if (abs(uv.x) > hw || abs(uv.y) > hh || (bare && scene[at + 23u] != 0u && in_opening(at, uv))) {
        return no_hit();
    }
    if (front) {
        return Hit(s, q, n, t, solid(at, cell_at(at, uv.x, uv.y), uv));
    }
    return Hit(s, q, -n, t, NO_CELL);
}

// ---- Cylindrical shells ----
// A shell's words: centre (0), axis (3), e1 (6, angle 0), e2 (9, e1 × axis), half the unrolled
// width (12), half the length (13), then as a rectangle's, and its radius (26), the side sprayed
// (28: +1 inside, −1 outside), its start angle (30) and whether its grid wraps (31).

// atan2(y, x) to about 10⁻⁷ rad (Abramowitz & Stegun 4.4.49 on the octant-reduced argument):
// drivers may take the built-in to 4096 ulp (10⁻³ rad near π), a cell on a 3 m lining.
fn atan2_fine(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let big = max(ax, ay);
    if (big == 0.0) {
        return 0.0;
    }
    let a = min(ax, ay) / big;
    let a2 = a * a;
    var r = a * (0.9999993329 + a2 * (-0.3332985605 + a2 * (0.1994653599 + a2 * (-0.1390853351
        + a2 * (0.0964200441 + a2 * (-0.0559098861 + a2 * (0.0218612288 + a2 * -0.0040540580)))))));
    if (ay > ax) {
        r = 1.5707963 - r;
    }
    if (x < 0.0) {
        r = 3.1415927 - r;
    }
    return select(r, -r, y < 0.0);
}

// The shell's unrolled coordinates of `p` (as the engine's `ShellChart::local`): u (m along the
// arc from the middle, the viewer's right from the side sprayed), v (m along the axis) and the
// height above the surface on the side sprayed (m); w: whether the shell covers p's angle and
// axial position.
fn shell_local(at: u32, p: vec3<f32>) -> vec4<f32> {
    let d = p - v3(at);
    let r = length(d - v3(at + 3u) * dot(d, v3(at + 3u)));
    let z = dot(d, v3(at + 3u));
    let radius = f(at + 26u);
    let sense = f(at + 28u);
    let span = 2.0 * f(at + 12u) / radius;
    // The angle from the start, in [0, 2π).
    var rel = atan2_fine(dot(d, v3(at + 9u)), dot(d, v3(at + 6u))) - f(at + 30u);
    rel -= 6.2831853 * floor(rel / 6.2831853);
    var mid = rel - 0.5 * span;
    if (mid > 3.1415927) {
        mid -= 6.2831853;
    }
    // A whole turn covers every angle, whatever f32 makes of its span.
    let covered = (scene[at + 31u] != 0u || rel <= span) && abs(z) <= f(at + 13u);
    return vec4<f32>(sense * radius * mid, z, sense * (radius - r), select(0.0, 1.0, covered));
}

// The unit normal of the shell at `p` towards the side sprayed.
fn shell_normal(at: u32, p: vec3<f32>) -> vec3<f32> {
    let d = p - v3(at);
    let radial = d - v3(at + 3u) * dot(d, v3(at + 3u));
    return -f(at + 28u) * radial / max(length(radial), 1e-30);
}

// The first fraction of the segment at which it crosses the height `level` above the shell
// going down (`down`: towards the surface from the side sprayed) or up; NONE if it does not.
fn shell_level(at: u32, p0: vec3<f32>, p1: vec3<f32>, level: f32, down: bool) -> f32 {
    let axis = v3(at + 3u);
    let m = p0 - v3(at);
    let d = p1 - p0;
    let mp = m - axis * dot(m, axis);
    let dp = d - axis * dot(d, axis);
    let rho = f(at + 26u) - f(at + 28u) * level;
    let a = dot(dp, dp);
    let b = dot(mp, dp);
    let c = dot(mp, mp) - rho * rho;
    let disc = b * b - a * c;
    if (a <= 0.0 || disc <= 0.0 || rho <= 0.0) {
        return NONE;
    }
    // Stable roots of a t² + 2 b t + c.
    let q = -(b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
    let r1 = q / a;
    let r2 = c / q;
    // Going down on the inside is moving away from the axis; on the outside, towards it.
    let away = f(at + 28u) > 0.0;
    for (var k = 0u; k < 2u; k++) {
        let t = select(max(r1, r2), min(r1, r2), k == 0u);
        let outward = dot(mp + dp * t, dp) > 0.0;
        if (t >= 0.0 && t <= 1.0 && (outward == away) == down) {
            return t;
        }
    }
    return NONE;
}

// The first hit of a segment that starts on the side sprayed of shell t (at `at`): its layer
// (`layer_crossing`), or the bare surface (alone where not `layered`: a step that started
// behind the surface meets no layer, as on the CPU); an opening lets a bare crossing pass.
fn shell_front(t: u32, at: u32, p0: vec3<f32>, p1: vec3<f32>, layered: bool) -> Hit {
    let top = band(t);
    let l0 = shell_local(at, p0);
    let h0 = l0.z;
    // The layer under the start, where the shell lies under it (past its edge, none).
    var own = 0.0;
    if (h0 <= top && l0.w > 0.0) {
        own = shell_layer(at, l0);
    }
    var s = NONE;
    var bare = true;
    if (h0 <= own || !layered) {
        // Inside the layer: within one step it meets only the bare surface.
        s = shell_level(at, p0, p1, 0.0, true);
    } else {
        // Into the band the layer may fill: where it crosses the bare surface (or its end, if
        // it stops short of it), then the layer's height in the cell under that.
        var enters = 0.0;
        if (h0 > top) {
            enters = shell_level(at, p0, p1, top, true);
        }
        if (enters > 1.0) {
            return no_hit();
        }
        let crossing = layer_crossing(at, p0, p1, vec2<f32>(h0, 0.0));
        s = crossing.x;
        bare = crossing.y > 0.0;
    }
    if (s > 1.0) {
        return no_hit();
    }
    let q = p0 + (p1 - p0) * s;
    let l = shell_local(at, q);
    let uv = l.xy;
    if (l.w == 0.0 || (bare && scene[at + 23u] != 0u && in_opening(at, uv))) {
        return no_hit();
    }
    return Hit(s, q, shell_normal(at, q), t, solid(at, cell_at(at, uv.x, uv.y), uv));
}

// The first hit of the segment on shell t: from the side sprayed, as `shell_front`; from behind,
// its bare back, or, where the path passes the shell's edge or an opening there, what it meets
// on the side sprayed beyond; from the side sprayed of a shell seen from outside, past its edge
// or through an opening, the back of its far side.
fn shell_hit(t: u32, p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    let at = M.tables.y + TARGET_WORDS * t;
    let h0 = shell_local(at, p0).z;
    var passed = 0.0;
    if (h0 > 0.0) {
        let front = shell_front(t, at, p0, p1, true);
        if (front.t <= 1.0) {
            return front;
        }
        // What passed now lies behind: on a shell seen from outside, inside the cylinder.
        passed = shell_level(at, p0, p1, 0.0, true);
        if (passed > 1.0) {
            return no_hit();
        }
    }
    let b = shell_level(at, p0, p1, 0.0, false);
    if (b > 1.0 || b < passed) {
        return no_hit();
    }
    let q = mix(p0, p1, b);
    let l = shell_local(at, q);
    if (l.w > 0.0 && !(scene[at + 23u] != 0u && in_opening(at, l.xy))) {
        return Hit(b, q, -shell_normal(at, q), t, NO_CELL);
    }
    if (h0 > 0.0) {
        return no_hit();
    }
    // Past the edge from behind, onto the side sprayed: its bare surface alone within the step.
    let rest = shell_front(t, at, q, p1, false);
    if (rest.t > 1.0) {
        return no_hit();
    }
    return Hit(b + (1.0 - b) * rest.t, rest.point, rest.normal, t, rest.cell);
}

// Whether the box at `at` (BOX_WORDS) overlaps the one from `lo` to `hi` (touching counts).
fn overlaps(at: u32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    return all(lo <= v3(at + 4u)) && all(v3(at) <= hi);
}

// The segment's first hit of all the member's surfaces: every target's, and the shapes' whose
// bounding box its own overlaps (a shape outside it cannot be met; most steps are far from all
// of them, and skip them with one test of the box around them all).
fn first_hit(p0: vec3<f32>, p1: vec3<f32>) -> Hit {
    var best = no_hit();
    for (var t = 0u; t < M.sizes.x; t++) {
        let h = target_hit(t, p0, p1);
        if (h.t < best.t) {
            best = h;
        }
    }
    let lo = min(p0, p1);
    let hi = max(p0, p1);
    if (!overlaps(M.tables.z, lo, hi)) {
        return best;
    }
    for (var k = 0u; k < M.sizes.y; k++) {
        let at = M.tables.z + BOX_WORDS + SHAPE_WORDS * k;
        if (!overlaps(at + 16u, lo, hi)) {
            continue;
        }
        let h = shape_hit(at, p0, p1);
        if (h.t < best.t) {
            best = h;
        }
    }
    return best;
}

// ---- Impact laws ----

// The mean thickness over the cells whose centres lie within `radius` (m) of `cell`'s (round a
// shell's full turn, openings left out), over at most 25 × 25 of them (a wider disc is sampled
// with a stride), m.
fn cushion(t: u32, cell: u32, radius: f32) -> f32 {
    let at = M.tables.y + TARGET_WORDS * t;
    let first = first_cell(at);
    let cols = i32(scene[at + 14u]);
    let rows = i32(scene[at + 15u]);
    let dx = 2.0 * f(at + 12u) / f32(cols);
    let dy = 2.0 * f(at + 13u) / f32(rows);
    let rx = i32(floor(radius / dx));
    let ry = i32(floor(radius / dy));
    if (rx == 0 && ry == 0) {
        return thickness[first + cell];
    }
    let stride = max(1, (max(rx, ry) + 11) / 12);
    let row = i32(cell) / cols;
    let col = i32(cell) % cols;
    var sum = 0.0;
    var n = 0.0;
    if (stride == 1 && scene[at + 24u] == 0u && scene[at + 31u] == 0u) {
        // No holes, no wrap, every cell: a row's cells in the disc are those within `half`
        // columns of the struck one (the test below is monotone in the offset), summed as one
        // span (`span_sum`) without a test per cell, in the same order and so to the same bits.
        for (var j = -ry; j <= ry; j++) {
            let r = row + j;
            let y = f32(j) * dy;
            var half = rx;
            while (half >= 0 && (f32(half) * dx) * (f32(half) * dx) + y * y > radius * radius) {
                half--;
            }
            if (r < 0 || r >= rows || half < 0) {
                continue;
            }
            let start = first + u32(r * cols);
            let lo = start + u32(max(col - half, 0));
            let last = start + u32(min(col + half, cols - 1));
            sum = span_sum(sum, lo, last);
            n += f32(last - lo + 1u);
        }
        return sum / max(n, 1.0);
    }
    for (var j = -ry; j <= ry; j += stride) {
        let r = row + j;
        if (r < 0 || r >= rows) {
            continue;
        }
        for (var i = -rx; i <= rx; i += stride) {
            let k = column(at, col + i);
            let x = f32(i) * dx;
            let y = f32(j) * dy;
            if (k < 0 || x * x + y * y > radius * radius || is_hole(at, u32(r * cols + k))) {
                continue;
            }
            sum += thickness[first + u32(r * cols + k)];
            n += 1.0;
        }
    }
    return sum / max(n, 1.0);
}

// `sum` plus the layers' thicknesses from cell `first` to cell `last` (over all grids), added
// one by one in that order. Eight cells are read at a time, all before any is added: an impact
// waits on its reads once per eight cells, not once per cell (on a GPU, the cushion's reads one
// after the other set the length of an epoch, which lasts as long as its slowest particle).
fn span_sum(sum: f32, first: u32, last: u32) -> f32 {
    var s = sum;
    for (var c = first; c <= last; c += 8u) {
        let a = vec4<f32>(thickness[c], thickness[min(c + 1u, last)], thickness[min(c + 2u, last)],
            thickness[min(c + 3u, last)]);
        let b = vec4<f32>(thickness[min(c + 4u, last)], thickness[min(c + 5u, last)],
            thickness[min(c + 6u, last)], thickness[min(c + 7u, last)]);
        let left = last - c;
        s += a.x;
        if (left >= 1u) { s += a.y; }
        if (left >= 2u) { s += a.z; }
        if (left >= 3u) { s += a.w; }
        if (left >= 4u) { s += b.x; }
        if (left >= 5u) { s += b.y; }
        if (left >= 6u) { s += b.z; }
        if (left >= 7u) { s += b.w; }
    }
    return s;
}

// Σ cᵢ xⁱ with x = θ / 90°, clamped to [0, 1], from n coefficients at `at`.
fn polynomial(at: u32, n: u32, theta: f32) -> f32 {
    let x = theta / 1.5707963;
    var acc = 0.0;
    for (var k = n; k > 0u; k--) {
        acc = acc * x + f(at + k - 1u);
    }
    return clamp(acc, 0.0, 1.0);
}

// The cushion law's grain diameter for the material draw m (m; negative: mortar).
fn grain(model: u32, m: f32) -> f32 {
    let frac = f(model + 16u);
    let q = (m - (1.0 - frac)) / frac;
    if (frac <= 0.0 || q < 0.0) {
        return -1.0;
    }
    let g = model + 20u;
    let n = scene[model + 19u];
    if (n < 2u) {
        return f(g);
    }
    let qq = min(q, 1.0);
    // The first sieve whose passing share exceeds q, clamped to [1, n - 1].
    var k = 1u;
    while (k < n - 1u && f(g + 2u * k + 1u) <= qq) {
        k++;
    }
    let d0 = f(g + 2u * (k - 1u));
    let s0 = f(g + 2u * (k - 1u) + 1u);
    let d1 = f(g + 2u * k);
    let s1 = f(g + 2u * k + 1u);
    if (s1 <= s0) {
        return d1;
    }
    let w = clamp((qq - s0) / (s1 - s0), 0.0, 1.0);
    return exp(log(d0) + w * (log(d1) - log(d0)));
}

// p_r of the law of `model` (word offset).
fn rebound_law(model: u32, theta: f32, layer: f32, has_layer: bool, material: f32, bounced: bool) -> f32 {
    let kind = scene[model + 6u];
    if (kind == 0u) {
        return 1.0;
    }
    if (kind == 1u) {
        return 0.0;
    }
    let ricochet = polynomial(model + 8u, scene[model + 7u], theta);
    if (kind == 2u) {
        return ricochet;
    }
    let d = grain(model, material);
    if (d < 0.0 || (bounced && has_layer && layer >= f(model + 18u) * d)) {
        return 0.0;
    }
    if (layer < f(model + 17u) * d) {
        return 1.0;
    }
    return clamp(ricochet / f(model + 16u), 0.0, 1.0);
}

// A unit direction within `half` (rad) of unit `axis`, uniform over the cone's solid angle.
fn scatter(axis: vec3<f32>, half_angle: f32, u1: f32, u2: f32) -> vec3<f32> {
    if (half_angle <= 0.0) {
        return axis;
    }
    let cos_t = 1.0 - u1 * (1.0 - cos(half_angle));
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let phi = 6.2831853 * u2;
    let sg = select(-1.0, 1.0, axis.z >= 0.0);
    let a = -1.0 / (sg + axis.z);
    let b = axis.x * axis.y * a;
    let e1 = vec3<f32>(1.0 + sg * axis.x * axis.x * a, sg * b, -sg * axis.x);
    let e2 = vec3<f32>(b, sg + axis.y * axis.y * a, -axis.y);
    return normalize(axis * cos_t + (e1 * cos(phi) + e2 * sin(phi)) * sin_t);
}

// ---- One particle ----

var<private> P: Particle;

fn flags() -> u32 {
    return (P.status >> 12u) & 15u;
}

fn set_flags(bits: u32) {
    P.status = (P.status & 0xfffu) | (bits << 12u);
}

fn impacts() -> u32 {
    return P.status & 0xfffu;
}

// The volume the particle carries, quanta: the nozzle's, or a released particle's own.
fn quanta() -> vec2<u32> {
    if ((flags() & RELEASED) == 0u) {
        return vec2<u32>(M.sizes.w, 0u);
    }
    var lo = 0u;
    var hi = M.sizes.z;
    let table = M.tables.w;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (scene[table + 3u * mid] < P.id) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if (lo < M.sizes.z && scene[table + 3u * lo] == P.id) {
        return vec2<u32>(scene[table + 3u * lo + 1u], scene[table + 3u * lo + 2u]);
    }
    return vec2<u32>(0u, 0u);
}

// Resolves the impact `h` with velocity `v_in`; books it. Returns the rebound velocity, with
// w = 1, or w = 0 if the particle stuck (and left flight).
fn impact(h: Hit, v_in: vec3<f32>, q: vec2<u32>) -> vec4<f32> {
    let on_target = h.owner < OBSTACLE;
    let front = on_target && h.cell != NO_CELL;
    let model = M.tables.x + MODEL_WORDS * select(M.sizes.x + (h.owner - OBSTACLE), h.owner, on_target);
    let fl = flags();
    let bounced = (fl & BOUNCED) != 0u;
    let released = (fl & RELEASED) != 0u;
    var layer = 0.0;
    if (front) {
        layer = cushion(h.owner, h.cell, f(model + 5u));
    }
    let material = uniform01(P.id, MATERIAL_EVENT, 0u);
    let speed = length(v_in);
    // The angle of incidence θ from the normal, from its cosine and sine with the arctangent of
    // our own: drivers may take `acos` to 2·10⁻⁴ rad (lavapipe does), which would move the
    // rebound laws' p_r(θ) by as much.
    var cos_theta = 1.0;
    var sin_theta = 0.0;
    if (speed > 0.0) {
        var n = h.normal;
        cos_theta = clamp(-dot(v_in, n) / speed, 0.0, 1.0);
        if (front) {
            // On a layer, θ is taken on the bare surface (as the field's curves are).
            n = bare_normal(M.tables.y + TARGET_WORDS * h.owner, h.point);
            cos_theta = min(abs(dot(v_in, n)) / speed, 1.0);
        }
        sin_theta = min(length(cross(v_in, n)) / speed, 1.0);
    }
    let theta = select(atan2_fine(sin_theta, cos_theta), 1.5707964, cos_theta == 0.0);
    let p = clamp(f(model) * rebound_law(model, theta, layer, front, material, bounced), 0.0, 1.0);
    let event = impacts();
    var stuck = true;
    var loose = false;
    var v_out = vec3<f32>(0.0);
    if (uniform01(P.id, event, 0u) < p) {
        let out_speed = speed * f(model + 1u);
        if (out_speed < f(model + 3u) && h.normal.z >= f(model + 4u)) {
            loose = true;
        } else {
            stuck = false;
            let reflected = v_in - 2.0 * min(dot(v_in, h.normal), 0.0) * h.normal;
            var axis = h.normal;
            if (dot(reflected, reflected) > 0.0) {
                axis = normalize(reflected);
            }
            var dir = scatter(axis, f(model + 2u), uniform01(P.id, event, 1u), uniform01(P.id, event, 2u));
            if (dot(dir, h.normal) < 0.0) {
                dir = dir - 2.0 * dot(dir, h.normal) * h.normal;
            }
            v_out = dir * out_speed;
        }
    }
    book(h, front, stuck, loose, bounced, released, q);
    if (front) {
        erode(h, v_in, speed, q);
    }
    if (stuck) {
        set_flags(flags() & ~ALIVE);
        return vec4<f32>(0.0);
    }
    set_flags(flags() | BOUNCED);
    return vec4<f32>(v_out, 1.0);
}

// ---- Erosion ----

// The volume (m³) the erosion law at `at` removes in one impact of `mass` (kg) at `speed`
// (m/s), `s` the sine of its angle γ from the surface: Finnie's k m v² f(γ), or Oka's
// g(γ) E90 (v / v_ref)^k₂ m with g(γ) = sin^n₁ γ (1 + Hv (1 − sin γ))^n₂ (`process/erosion`).
// The angle is never formed: drivers may take `asin` or `tan` to a few 10⁻⁴ (Vulkan allows
// `atan` 4096 ulp), which would move f(γ) by as much; its sine and cosine are exact enough.
fn removed(at: u32, mass: f32, speed: f32, s: f32) -> f32 {
    if (scene[at] == 0u) {
        // tan γ ≤ 1/3: sin 2γ − 3 sin² γ; beyond, cos² γ / 3.
        let c = sqrt(max(1.0 - s * s, 0.0));
        let shape = select(c * c / 3.0, 2.0 * s * c - 3.0 * s * s, 3.0 * s <= c);
        return f(at + 1u) * mass * speed * speed * max(shape, 0.0);
    }
    if (s <= 0.0 || speed <= 0.0) {
        return 0.0;
    }
    let g = pow(s, f(at + 2u)) * pow(1.0 + f(at + 4u) * (1.0 - s), f(at + 3u));
    return g * f(at + 1u) * pow(speed / f(at + 6u), f(at + 5u)) * mass;
}

// `volume` (m³) in wear quanta (`per_m3` of them a cubic metre), rounded to the nearest, as
// (low, high); none for a volume that is not positive.
fn wear_quanta(volume: f32, per_m3: f32) -> vec2<u32> {
    let q = round(volume * per_m3);
    if (!(q > 0.0)) {
        return vec2<u32>(0u);
    }
    let hi = floor(q / 4294967296.0);
    return vec2<u32>(u32(q - hi * 4294967296.0), u32(min(hi, 4294967295.0)));
}

// Books the coating and substrate that the impact `h` on a target's front with velocity `v_in`
// (of `speed`) by `q` quanta of material would wear away, in the struck cell, where the target
// erodes.
fn erode(h: Hit, v_in: vec3<f32>, speed: f32, q: vec2<u32>) {
    let at = M.tables.y + TARGET_WORDS * h.owner;
    if (scene[at + 25u] == 0u) {
        return;
    }
    let e = own(scene[at + 25u]);
    // sin γ, γ the impact angle from the surface.
    let s = clamp(-dot(v_in, h.normal) / max(speed, 1e-30), 0.0, 1.0);
    let mass = (f32(q.y) * 4294967296.0 + f32(q.x)) * f(e);
    let cell = 4u * (first_cell(at) + h.cell);
    add_wear(cell, wear_quanta(removed(e + 2u, mass, speed, s), f(e + 1u)));
    add_wear(cell + 2u, wear_quanta(removed(e + 2u + LAW_WORDS, mass, speed, s), f(e + 1u)));
}

fn book(h: Hit, front: bool, stuck: bool, loose: bool, bounced: bool, released: bool, q: vec2<u32>) {
    if (h.owner >= OBSTACLE) {
        let o = h.owner - OBSTACLE;
        atomicAdd(&counters[obstacle_slot(o, OB_HITS)], 1u);
        if (stuck) {
            count_at(obstacle_slot(o, select(OB_STUCK, OB_RECEIVED, released)), q);
        }
        return;
    }
    let t = h.owner;
    let at = M.tables.y + TARGET_WORDS * t;
    atomicAdd(&counters[target_slot(t, TG_HITS)], 1u);
    if (stuck) {
        if (released) {
            count_at(target_slot(t, TG_RECEIVED), q);
            if (!front) {
                add64(target_slot(t, TG_RECEIVED_BACK), q);
            }
        } else if (!front) {
            count_at(target_slot(t, TG_STUCK_BACK), q);
        } else {
            count_at(target_slot(t, TG_STUCK), q);
            if (loose) {
                count_at(target_slot(t, TG_LOOSE), q);
            } else if (bounced) {
                count_at(target_slot(t, TG_TRAPPED), q);
            }
        }
    }
    if (front && scene[at + 18u] != 0u && (flags() & HIT_SUBSTRATE) == 0u) {
        set_flags(flags() | HIT_SUBSTRATE);
        count_at(target_slot(t, TG_DELIVERED), q);
        tally(T_FIRST, q);
        if (!stuck) {
            tally(T_FIRST_REBOUND, q);
        }
    }
    if (!front) {
        return;
    }
    let first = first_cell(at);
    atomicAdd(&cells[4u * (first + h.cell) + 2u], 1u);
    mark(first + h.cell);
    if (stuck) {
        splat(at, first, h.cell, q);
    }
}

// The deposit shared evenly over the footprint's cells inside the grid (round a shell's full
// turn) and not cut away, the struck cell (always solid) first.
fn splat(at: u32, first: u32, cell: u32, q: vec2<u32>) {
    let cols = i32(scene[at + 14u]);
    let rows = i32(scene[at + 15u]);
    let offsets = own(scene[at + 19u]);
    let count = scene[at + 20u];
    let row = i32(cell) / cols;
    let col = i32(cell) % cols;
    var n = 0u;
    for (var k = 0u; k < count; k++) {
        let c = column(at, col + bitcast<i32>(scene[offsets + 2u * k]));
        let r = row + bitcast<i32>(scene[offsets + 2u * k + 1u]);
        n += select(0u, 1u, c >= 0 && r >= 0 && r < rows && !is_hole(at, u32(r * cols + c)));
    }
    var j = 0u;
    for (var k = 0u; k < count; k++) {
        let c = column(at, col + bitcast<i32>(scene[offsets + 2u * k]));
        let r = row + bitcast<i32>(scene[offsets + 2u * k + 1u]);
        if (c >= 0 && r >= 0 && r < rows && !is_hole(at, u32(r * cols + c))) {
            deposit(first + u32(r * cols + c), share(q, n, j));
            j++;
        }
    }
}

// One full step s: the impacts, then the checks for leaving the domain and expiring.
fn full_step(s: u32) {
    let q = quanta();
    var x = vec3<f32>(P.x, P.y, P.z);
    var v = vec3<f32>(P.vx, P.vy, P.vz);
    var remaining = M.gravity_dt.w;
    for (var k = 0u; k < M.run.w; k++) {
        let end = advance(x, v, remaining);
        let h = first_hit(x, end.x);
        if (h.t > 1.0) {
            x = end.x;
            v = end.v;
            break;
        }
        P.status = (P.status & 0xf000u) | min(impacts() + 1u, MAX_IMPACTS);
        var hit = h;
        var v_in = mix(v, end.v, h.t);
        if (h.cell != NO_CELL) {
            // Entering a taller column from its side meets the side, not the layer's top: its
            // normal opposes the motion along the face.
            let along = v_in - h.normal * dot(v_in, h.normal);
            if (dot(v_in, h.normal) >= 0.0 && dot(along, along) > 0.0) {
                hit.normal = -normalize(along);
            }
        } else if (dot(v_in, h.normal) >= 0.0) {
            let chord = end.x - x;
            if (dot(chord, chord) > 0.0) {
                v_in = normalize(chord) * length(v_in);
            }
        }
        let res = impact(hit, v_in, q);
        if (res.w == 0.0) {
            P.x = h.point.x;
            P.y = h.point.y;
            P.z = h.point.z;
            P.vx = 0.0;
            P.vy = 0.0;
            P.vz = 0.0;
            return;
        }
        x = h.point + hit.normal * SURFACE_OFFSET;
        v = res.xyz;
        remaining *= 1.0 - h.t;
    }
    P.x = x.x;
    P.y = x.y;
    P.z = x.z;
    P.vx = v.x;
    P.vy = v.y;
    P.vz = v.z;
    let released = (flags() & RELEASED) != 0u;
    let age = f32(s + 1u - P.born);
    let left = any(x < M.min_drag.xyz) || any(x > M.max_life.xyz);
    if (!left && age <= M.max_life.w && impacts() < MAX_IMPACTS) {
        return;
    }
    var slot = T_EXPIRED;
    if (released) {
        slot = select(T_RELEASED_EXPIRED, T_RELEASED_LEFT, left);
    } else if (impacts() == 0u) {
        slot = T_OVERSPRAY;
    } else if (left) {
        slot = T_LEFT;
    }
    tally(slot, q);
    set_flags(flags() & ~ALIVE);
}

// Flies particle i (of member `M`) through the epoch's steps; returns the steps it took.
fn fly_one(i: u32) -> u32 {
    if (i >= params.steps.z) {
        return 0u;
    }
    P = particles[i];
    // Retired (or a slot that pads a member to whole workgroups), or born in a later epoch.
    if ((flags() & ALIVE) == 0u || P.born >= params.steps.y) {
        return 0u;
    }
    var s = max(params.steps.x, P.born);
    var steps = 0u;
    while (s < params.steps.y && (flags() & ALIVE) != 0u) {
        full_step(s);
        s++;
        steps++;
    }
    particles[i] = P;
    return steps;
}

// The particle-steps of a workgroup, added up there before one addition to its member's.
var<workgroup> group_steps: atomic<u32>;

// The first slot of workgroup `wid`, its member read into `M`; NO_SLOT past every member's
// slots. Each member's slots fill whole workgroups, so a workgroup holds one member's particles.
fn group_first(wid: vec3<u32>) -> u32 {
    let first = wid.x * 64u + wid.y * params.steps.w;
    if (first >= params.steps.z) {
        return NO_SLOT;
    }
    load_member(member_of(first));
    return first;
}

@compute @workgroup_size(64)
fn fly(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let first = group_first(wid);
    if (first == NO_SLOT) {
        return;
    }
    let i = first + lid;
    if (lid == 0u) {
        atomicStore(&group_steps, 0u);
    }
    workgroupBarrier();
    atomicAdd(&group_steps, fly_one(i));
    workgroupBarrier();
    if (lid == 0u) {
        add64(M.place.w + C_STEPS, vec2<u32>(atomicLoad(&group_steps), 0u));
    }
}

// At a call's start: the layers the epochs read (the first half) are the layers as the call
// found them (the second), whatever the last call left there.
@compute @workgroup_size(64)
fn restore(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.x + gid.y * params.steps.w;
    if (c > params.sizes.z) {
        return;
    }
    thickness[c] = thickness[params.sizes.z + 1u + c];
}

// One workgroup: the cells listed and each target's band, copied into `plan`, and the size of
// the dispatches over the listed cells into `listed_groups`.
@compute @workgroup_size(64)
fn census(@builtin(local_invocation_index) lid: u32) {
    if (lid == 0u) {
        let count = atomicLoad(&counters[C_LISTED]);
        plan[0] = count;
        let groups = (count + 63u) / 64u;
        let row = params.steps.w / 64u;
        listed_groups[0] = min(groups, row);
        listed_groups[1] = (groups + row - 1u) / row;
        listed_groups[2] = 1u;
    }
    let table = MEMBER_WORDS * params.sizes.x;
    for (var t = lid; t < params.sizes.y; t += 64u) {
        plan[1u + t] = atomicLoad(&counters[scene[table + TABLE_WORDS * t + 2u]]);
    }
}

// Copies each listed cell's deposit and impacts beside it (and its wear, where a target erodes,
// into the listed part of `wear`) and clears the cell for the next call.
@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x + gid.y * params.steps.w;
    if (k >= plan[0]) {
        return;
    }
    let c = listed[4u * k];
    listed[4u * k + 1u] = atomicExchange(&cells[4u * c], 0u);
    listed[4u * k + 2u] = atomicExchange(&cells[4u * c + 1u], 0u);
    listed[4u * k + 3u] = atomicExchange(&cells[4u * c + 2u], 0u);
    atomicStore(&cells[4u * c + 3u], 0u);
    if (params.sizes.w != 0u) {
        let copy = 4u * (params.sizes.z + 1u + k);
        for (var j = 0u; j < 4u; j++) {
            atomicStore(&wear[copy + j], atomicExchange(&wear[4u * c + j], 0u));
        }
    }
}

// At the end of an epoch within a call: each listed cell's layer as the call found it plus what
// the call has deposited on it so far (quanta × the quantum's thickness on one of the target's
// cells), as the engine settles an epoch; the target's band is raised to it.
@compute @workgroup_size(64)
fn settle(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x + gid.y * params.steps.w;
    if (k >= plan[0]) {
        return;
    }
    let c = listed[4u * k];
    let lo = atomicLoad(&cells[4u * c]);
    let hi = atomicLoad(&cells[4u * c + 1u]);
    if (lo == 0u && hi == 0u) {
        return;
    }
    // The target whose grid holds the cell: the last whose first cell is not past it.
    let table = MEMBER_WORDS * params.sizes.x;
    var t = 0u;
    var end = params.sizes.y;
    while (end - t > 1u) {
        let mid = (t + end) / 2u;
        if (scene[table + TABLE_WORDS * mid] <= c) {
            t = mid;
        } else {
            end = mid;
        }
    }
    let per_quantum = f(table + TABLE_WORDS * t + 1u);
    let quanta = f32(hi) * 4294967296.0 + f32(lo);
    let layer = max(thickness[params.sizes.z + 1u + c] + quanta * per_quantum, 0.0);
    thickness[c] = layer;
    // Raised only by the cells above it: few, as a layer grows slowly.
    if (layer > bitcast<f32>(plan[1u + t])) {
        atomicMax(&counters[scene[table + TABLE_WORDS * t + 2u]], bitcast<u32>(layer));
    }
}
