// Composes two eye images into one frame: interleaved rows (first eye on
// even rows, counting from 0 at the top), interleaved columns (first eye on
// even columns), or a red-cyan anaglyph (red from the first eye, green and
// blue from the second). MODE is a pipeline constant (0, 1, 2).

@group(0) @binding(0) var first_eye: texture_2d<f32>;
@group(0) @binding(1) var second_eye: texture_2d<f32>;

override MODE: u32 = 0u;

@vertex
fn vs_full(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(vi & 1u) * 4 - 1);
    let y = f32(i32(vi >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn fs_compose(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(pos.xy);
    let a = textureLoad(first_eye, q, 0);
    let b = textureLoad(second_eye, q, 0);
    if (MODE == 0u) {
        return select(b, a, (q.y & 1) == 0);
    }
    if (MODE == 1u) {
        return select(b, a, (q.x & 1) == 0);
    }
    return vec4<f32>(a.r, b.g, b.b, 1.0);
}
