// The newborns of a call, sampled in their slots where they will fly: `born`, once at the
// call's start, is the GPU twin of the engine's `Emitter::sample`, each newborn drawing from
// its own stream (seed, id, BIRTH_EVENT, draw). A member's slots hold its swarm (uploaded),
// then its newborns in id order, then padding to whole workgroups, which `born` clears. The
// layouts are written by `births.rs`, whose constants these mirror; this file is compiled
// after `flight.wgsl`, whose bindings and helpers it uses.

// The event of a particle's stream its birth draws from (impacts count from 0; the material
// draw is MATERIAL_EVENT).
const BIRTH_EVENT: u32 = 0xfffffffeu;
const EMITTER_WORDS: u32 = 16u;
const BATCH_WORDS: u32 = 20u;
const TAU: f32 = 6.2831855;

// The batch (of `batches` at `at`) that holds the member's newborn n: the last whose first
// newborn is not past it.
fn batch_of(at: u32, batches: u32, n: u32) -> u32 {
    var lo = 0u;
    var hi = batches;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (scene[at + BATCH_WORDS * mid + 3u] <= n) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return at + BATCH_WORDS * lo;
}

// Acklam's approximation of Φ⁻¹ in the tail, at probability q (< 0.02425).
fn normal_tail(q: f32) -> f32 {
    let t = sqrt(-2.0 * log(q));
    let num = ((((-7.784894002430293e-3 * t - 3.223964580411365e-1) * t - 2.400758277161838) * t
        - 2.549671464120693) * t + 4.374664141464968) * t + 2.938163982698783;
    let den = (((7.784695709041462e-3 * t + 3.224671290700398e-1) * t + 2.445134137142996) * t
        + 3.754408661907416) * t + 1.0;
    return num / den;
}

// Φ⁻¹(p), the inverse of the standard normal distribution function: Acklam's rational
// approximation (relative error 1.2·10⁻⁹, below f32's), p kept within f32's reach of 0 and 1.
fn inverse_normal_cdf(p0: f32) -> f32 {
    let p = clamp(p0, 1e-37, 1.0 - 6e-8);
    if (p < 0.02425) {
        return normal_tail(p);
    }
    if (p > 1.0 - 0.02425) {
        return -normal_tail(1.0 - p);
    }
    let q = p - 0.5;
    let r = q * q;
    let num = (((((-3.969683028665376e1 * r + 2.209460984245205e2) * r - 2.759285104469687e2) * r
        + 1.38357751867269e2) * r - 3.066479806614716e1) * r + 2.506628277459239) * q;
    let den = ((((-5.447609879822406e1 * r + 1.615858368580409e2) * r - 1.556989798598866e2) * r
        + 6.680131188771972e1) * r - 1.328068155288572e1) * r + 1.0;
    return num / den;
}

// The draw of N(μ, σ) truncated to [0, 1] (the emitter's words at `e`) for the uniform u, by
// inverting its distribution function in the tail the engine's sampler chose.
fn truncated_normal(e: u32, u: f32) -> f32 {
    let mu = f(e + 6u);
    let sigma = f(e + 7u);
    // σ ≤ 0 (or not a number): the mean, as the engine's sampler.
    if (!(sigma > 0.0)) {
        return clamp(mu, 0.0, 1.0);
    }
    let a = f(e + 8u);
    let b = f(e + 9u);
    var x = 0.0;
    if (scene[e + 10u] != 0u) {
        x = -inverse_normal_cdf(a - u * (a - b));
    } else {
        x = inverse_normal_cdf(a + u * (b - a));
    }
    return clamp(mu + sigma * x, 0.0, 1.0);
}

// Where on the aperture newborn `id` starts, along the width and height axes, m: uniform over
// a rectangle, a disc or a ring (draws 0 and 1).
fn aperture_offset(e: u32, id: u32) -> vec2<f32> {
    let kind = scene[e];
    let u0 = uniform01(id, BIRTH_EVENT, 0u);
    let u1 = uniform01(id, BIRTH_EVENT, 1u);
    if (kind == 0u) {
        return vec2<f32>(0.0);
    }
    if (kind == 2u) {
        return vec2<f32>(f(e + 1u) * (2.0 * u0 - 1.0), f(e + 2u) * (2.0 * u1 - 1.0));
    }
    var r0 = 0.0;
    var r1 = f(e + 1u);
    if (kind == 3u) {
        r0 = f(e + 1u);
        r1 = f(e + 2u);
    }
    let r = sqrt(r0 * r0 + u0 * (r1 * r1 - r0 * r0));
    // Azimuths in [−π, π), where drivers' sine and cosine keep their stated accuracy.
    let phi = TAU * (u1 - 0.5);
    return r * vec2<f32>(cos(phi), sin(phi));
}

// The unit direction of newborn `id` from the nozzle's pose in batch `b` (draws 2 and 3).
fn birth_direction(e: u32, b: u32, id: u32) -> vec3<f32> {
    let axis = v3(b + 7u);
    let across = v3(b + 10u);
    let up = v3(b + 13u);
    let kind = scene[e + 3u];
    let u = uniform01(id, BIRTH_EVENT, 2u);
    let w = uniform01(id, BIRTH_EVENT, 3u);
    if (kind == 3u) {
        let a = f(e + 11u) * (u - 0.5);
        let c = f(e + 12u) * (w - 0.5);
        return normalize(axis + across * tan(a) + up * tan(c));
    }
    var s = 0.0;
    var c = 1.0;
    if (kind == 2u) {
        // Uniform in solid angle: 1 − cos θ uniform in [0, 1 − cos θ_half), its sine from it.
        let one_less = u * f(e + 5u);
        c = 1.0 - one_less;
        s = sqrt(max(one_less * (2.0 - one_less), 0.0));
    } else {
        var theta = f(e + 4u) * u;
        if (kind == 1u) {
            theta = f(e + 4u) * truncated_normal(e, u);
        }
        s = sin(theta);
        c = cos(theta);
    }
    let phi = TAU * (w - 0.5);
    return axis * c + (across * cos(phi) + up * sin(phi)) * s;
}

// Samples each newborn of each member into its slot (born in its batch's step, alive, no
// impact yet), and clears the padding after them.
@compute @workgroup_size(64)
fn born(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let first = group_first(wid);
    if (first == NO_SLOT) {
        return;
    }
    let i = first + lid;
    let local = i - M.place.x;
    if (local < M.births.z) {
        return;
    }
    let n = local - M.births.z;
    if (n >= M.births.w) {
        particles[i] = Particle(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0u, 0u);
        return;
    }
    let e = M.births.x;
    let b = batch_of(e + EMITTER_WORDS, M.births.y, n);
    let id = scene[b + 1u] + (n - scene[b + 3u]);
    let d = aperture_offset(e, id);
    let x = v3(b + 4u) + v3(b + 10u) * d.x + v3(b + 13u) * d.y;
    let speed = f(e + 13u) + (f(e + 14u) - f(e + 13u)) * uniform01(id, BIRTH_EVENT, 4u);
    let v = birth_direction(e, b, id) * speed + v3(b + 16u);
    particles[i] = Particle(x.x, x.y, x.z, v.x, v.y, v.z, scene[b], id, ALIVE << 12u);
}
