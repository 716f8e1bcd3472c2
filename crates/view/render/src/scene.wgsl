// spraysim's 3D view: lit triangles, coloured lines, particles as round sprites of a fixed
// size in pixels. Colours are bytes in, bytes out (the targets are non-sRGB), so a window
// and an offscreen image show the same values as the heatmaps.

struct Globals {
    view_proj: mat4x4<f32>,
    // eye position (xyz), lighting on (w > 0.5)
    eye: vec4<f32>,
    // viewport width and height in pixels (xy), point size in pixels (z)
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world: vec3<f32>,
};

@vertex
fn vs_mesh(@location(0) pos: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) color: vec4<f32>) -> MeshOut {
    var out: MeshOut;
    out.clip = globals.view_proj * vec4<f32>(pos, 1.0);
    out.color = color;
    out.normal = normal;
    out.world = pos;
    return out;
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    if (globals.eye.w < 0.5) {
        return in.color;
    }
    // A head light, two-sided: surfaces facing the eye keep their colour, grazing ones darken.
    let to_eye = normalize(globals.eye.xyz - in.world);
    let n = normalize(in.normal);
    let lambert = abs(dot(n, to_eye));
    return vec4<f32>(in.color.rgb * (0.45 + 0.55 * lambert), in.color.a);
}

struct FlatOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    @location(1) corner: vec2<f32>,
};

@vertex
fn vs_line(@location(0) pos: vec3<f32>, @location(1) color: vec4<f32>) -> FlatOut {
    var out: FlatOut;
    out.clip = globals.view_proj * vec4<f32>(pos, 1.0);
    out.color = color;
    out.corner = vec2<f32>(0.0, 0.0);
    return out;
}

// One instance a particle, drawn as a strip of two triangles whose four corners come from the
// vertex index (four vertices a particle rather than six: the vertex stage dominates).
@vertex
fn vs_point(@builtin(vertex_index) vi: u32, @location(0) center: vec3<f32>, @location(1) color: vec4<f32>) -> FlatOut {
    var corners = array<vec2<f32>, 4>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, 1.0),
    );
    let c = globals.view_proj * vec4<f32>(center, 1.0);
    // Half the size in clip units times w: a fixed size in pixels at any depth.
    let half = vec2<f32>(globals.viewport.z) / globals.viewport.xy;
    var out: FlatOut;
    out.clip = vec4<f32>(c.xy + corners[vi] * half * c.w, c.z, c.w);
    out.color = color;
    out.corner = corners[vi];
    return out;
}

@fragment
fn fs_flat(in: FlatOut) -> @location(0) vec4<f32> {
    // Particles of three pixels and more are round.
    if (globals.viewport.z >= 3.0 && dot(in.corner, in.corner) > 1.0) {
        discard;
    }
    return in.color;
}
