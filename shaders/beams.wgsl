// Beam strips for the tsm-contact viewport (src/app/canvas/beams_gpu.rs): screen-space triangle
// strips built on the CPU, positioned here from screen points to clip space, with a soft
// one-pixel edge computed from the signed distance across the strip. Output is premultiplied
// alpha in gamma space (what egui's blending expects), or linear for an sRGB target.

struct Uniforms {
    // Size of the whole render target in points.
    screen_size: vec2<f32>,
    // 1 if the target is an sRGB format (then colours are converted to linear).
    srgb_target: u32,
    _pad: u32,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

struct VertexIn {
    @location(0) pos: vec2<f32>,
    @location(1) color: vec4<f32>,
    @location(2) edge: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    // x: signed distance from the centre line (px), y: half width (px).
    @location(1) edge: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let ndc = vec2<f32>(2.0 * v.pos.x / u.screen_size.x - 1.0, 1.0 - 2.0 * v.pos.y / u.screen_size.y);
    out.clip = vec4<f32>(ndc, 0.0, 1.0);
    out.color = v.color;
    out.edge = v.edge;
    return out;
}

fn to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let coverage = clamp(in.edge.y - abs(in.edge.x) + 0.5, 0.0, 1.0);
    let a = in.color.a * coverage;
    var rgb = in.color.rgb;
    if (u.srgb_target == 1u) {
        rgb = to_linear(rgb);
    }
    return vec4<f32>(rgb * a, a);
}
