// Ray-cast sphere impostors: one instanced draw for every atom.
//
// Each atom is a quad built in the vertex shader, facing the eye and
// enlarged by d / sqrt(d² − r²) so it covers the sphere's perspective
// silhouette. The fragment shader intersects the eye ray with the exact
// sphere, shades the hit point and writes its true depth, so spheres
// intersect correctly. Everything is in view space: each molecule's
// model-view matrix is composed in f64 on the CPU, so large world
// coordinates never reach f32.

struct Frame {
    proj: mat4x4<f32>,
    // xyz: direction towards the light (view space, unit); w: ambient share.
    light: vec4<f32>,
    highlight: vec4<f32>,
};

struct Atom {
    // xyz: position relative to the molecule's centre; w: radius.
    pos_radius: vec4<f32>,
    // rgb: colour; a: molecule index (as float).
    color_body: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> atoms: array<Atom>;
@group(0) @binding(2) var<storage, read> model_view: array<mat4x4<f32>>;
// One bit per atom: in contact.
@group(0) @binding(3) var<storage, read> highlight: array<u32>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) @interpolate(flat) centre: vec3<f32>,
    @location(2) @interpolate(flat) radius: f32,
    @location(3) @interpolate(flat) color: vec3<f32>,
};

const CORNERS = array<vec2<f32>, 6>(
    vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
);

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let atom = atoms[ii];
    let body = u32(atom.color_body.w);
    let c = (model_view[body] * vec4<f32>(atom.pos_radius.xyz, 1.0)).xyz;
    let r = atom.pos_radius.w;
    let d = length(c);
    out.centre = c;
    out.radius = r;
    let lit = (highlight[ii / 32u] >> (ii % 32u)) & 1u;
    out.color = select(atom.color_body.rgb, frame.highlight.rgb, lit == 1u);
    if (d <= r * 1.0001) {
        // The eye is inside this sphere: draw nothing.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        out.view_pos = c;
        return out;
    }
    // A billboard through the centre, perpendicular to the eye ray, large
    // enough to contain the tangent cone's footprint.
    let w = -c / d;
    var up = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(w.y) > 0.99) {
        up = vec3<f32>(1.0, 0.0, 0.0);
    }
    let u = normalize(cross(up, w));
    let v = cross(w, u);
    let grow = r * d / sqrt(d * d - r * r);
    let corner = CORNERS[vi];
    let p = c + (u * corner.x + v * corner.y) * grow * 1.02;
    out.view_pos = p;
    out.clip = frame.proj * vec4<f32>(p, 1.0);
    return out;
}

struct FsOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_main(in: VsOut) -> FsOut {
    var out: FsOut;
    let dir = normalize(in.view_pos);
    let b = dot(dir, in.centre);
    let disc = b * b - (dot(in.centre, in.centre) - in.radius * in.radius);
    if (disc < 0.0) {
        discard;
    }
    let t = b - sqrt(disc);
    let hit = dir * t;
    let n = normalize(hit - in.centre);
    let l = frame.light.xyz;
    let diffuse = max(dot(n, l), 0.0);
    let h = normalize(l - dir);
    let spec = pow(max(dot(n, h), 0.0), 40.0) * 0.35;
    let ambient = frame.light.w;
    let shade = in.color * (ambient + (1.0 - ambient) * diffuse) + vec3<f32>(spec);
    out.color = vec4<f32>(shade, 1.0);
    let clip = frame.proj * vec4<f32>(hit, 1.0);
    out.depth = clip.z / clip.w;
    return out;
}
