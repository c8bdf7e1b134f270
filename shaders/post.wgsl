// Screen-space depth cues over a finished eye image: silhouette outlines
// where depth jumps and ambient occlusion of pixels in crevices.
//
// One full-screen triangle reads the eye's depth buffer and writes a grey
// factor that the blend state multiplies into the colour already there
// (result = colour × factor), so the colour is never copied. OUTLINE and AO
// are pipeline constants: the pass runs only when one of them is on.

struct Post {
    // x: near, y: far (view depths of depth 0 and 1), z, w: pixels per Å at 1 Å depth (x, y).
    depth: vec4<f32>,
    // x: outline depth jump (Å), y: outline darkness, z: occlusion radius (Å), w: occlusion strength.
    cue: vec4<f32>,
};

@group(0) @binding(0) var<uniform> post: Post;
@group(0) @binding(1) var depth_tex: texture_depth_2d;

override OUTLINE: bool = false;
override AO: bool = false;

@vertex
fn vs_full(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(vi & 1u) * 4 - 1);
    let y = f32(i32(vi >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

// View depth (Å, positive) at pixel q; the far plane for background.
fn view_depth(q: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth_tex));
    let d = textureLoad(depth_tex, clamp(q, vec2<i32>(0), size - 1), 0);
    let n = post.depth.x;
    let f = post.depth.y;
    return n * f / (f - d * (f - n));
}

const OFFSETS = array<vec2<i32>, 8>(
    vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1),
    vec2<i32>(2, 0), vec2<i32>(-2, 0), vec2<i32>(0, 2), vec2<i32>(0, -2),
);

const AO_SAMPLES: i32 = 16;

@fragment
fn fs_post(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(pos.xy);
    let z = view_depth(q);
    var k = 1.0;
    if (z >= post.depth.y * 0.9999) {
        // Background: nothing to darken.
        return vec4<f32>(1.0);
    }
    if (OUTLINE) {
        // The nearer side of a depth jump is the silhouette: darken it.
        var jump = 0.0;
        for (var i = 0; i < 8; i++) {
            jump = max(jump, view_depth(q + OFFSETS[i]) - z);
        }
        let t = smoothstep(post.cue.x, 2.0 * post.cue.x, jump);
        k *= 1.0 - post.cue.y * t;
    }
    if (AO) {
        // Samples on a spiral within the occlusion radius (projected at
        // this depth); a sample nearer than this pixel, but not by more
        // than the radius, occludes it.
        let radius_px = post.depth.zw * post.cue.z / z;
        var hidden = 0.0;
        for (var i = 0; i < AO_SAMPLES; i++) {
            let a = f32(i) * 2.39996;
            let s = sqrt((f32(i) + 0.5) / f32(AO_SAMPLES));
            let off = vec2<f32>(cos(a), sin(a)) * s * radius_px;
            let zs = view_depth(q + vec2<i32>(round(off)));
            let nearer = z - zs;
            if (nearer > 0.25 && nearer < 2.0 * post.cue.z) {
                hidden += 1.0;
            }
        }
        k *= 1.0 - post.cue.w * hidden / f32(AO_SAMPLES);
    }
    return vec4<f32>(k, k, k, 1.0);
}
