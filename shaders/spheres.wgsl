// Ray-cast sphere impostors: one instanced draw for every atom.
//
// Each atom is a quad built in the vertex shader, facing the eye and
// enlarged by d / sqrt(d² − r²) so it covers the sphere's perspective
// silhouette. The fragment shader intersects the eye ray with the exact
// sphere, shades the hit point and writes its true depth, so spheres
// intersect correctly. Everything is in view space: each molecule's
// model-view matrix is composed in f64 on the CPU, so large world
// coordinates never reach f32. A stereo eye sits at `frame.eye` in the mono
// view space; its projection is off-axis (built on the CPU).
//
// Variants (no cost when off): DEPTH_CUE is a pipeline constant;
// fs_shadowed (reads the shadow map, group 1) replaces fs_main when shadows
// are on; vs_light/fs_light draw the shadow map itself, orthographic from
// the light, with parallel rays.
//
// The ghost (GHOST, a pipeline constant) draws the drug's atoms again with
// the model-view matrix at `frame.ghost.w` (the reference pose) in one tint,
// 2 % smaller so that a drug sitting exactly on its reference hides it
// without depth ties; it is blended by the caller's pipeline.
//
// The clipping slab (`frame.slab`, on when z > 0.5): two planes of constant
// depth in the mono view space. A sphere's front surface beyond the far
// plane is discarded; one in front of the near plane shows its cut face on
// the near plane (a flat cap, as ChimeraX caps clipped atoms) when the
// sphere reaches through it, else nothing. The shadow map drops the atoms'
// parts outside the slab too. A cylinder shader clips with `slab_cut`.

struct Frame {
    proj: mat4x4<f32>,
    // xyz: direction towards the light (view space, unit); w: ambient share.
    light: vec4<f32>,
    highlight: vec4<f32>,
    // xyz: this eye's position in the mono view space.
    eye: vec4<f32>,
    // x: distance where fading starts, y: where it is strongest, z: strength.
    fog: vec4<f32>,
    background: vec4<f32>,
    // Mono view space → light space (a rotation and a shift; light looks down −z).
    light_view: mat4x4<f32>,
    // x: half extent of the map (Å), y: light-space z at depth 0, z: depth range (Å), w: bias (Å).
    shadow: vec4<f32>,
    // x: shadow map size (texels), y: how dark a full shadow is (0..1).
    shadow_b: vec4<f32>,
    // x: the slab's near plane (mono view-space z), y: its far plane, z: 1 when on.
    slab: vec4<f32>,
    // rgb: the ghost's tint; w: index of its model-view matrix.
    ghost: vec4<f32>,
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
// Four bits per atom, eight atoms a word: its highlight level.
@group(0) @binding(3) var<storage, read> highlight: array<u32>;

// The shown colour of an atom of colour `base` at highlight level `level`
// (four bits an atom, eight atoms a word): 0 none, 1 in contact (the
// highlight colour), 2 to PRESS_LEVELS pressed into the soft band, graded
// towards PRESSED_DEEP at the limit. Mirrors render::colors::contact_colour.
const PRESS_LEVELS: u32 = 8u;
const PRESSED_DEEP: vec3<f32> = vec3<f32>(1.0, 0.8, 0.0);

fn highlight_level(i: u32) -> u32 {
    return (highlight[i / 8u] >> (4u * (i % 8u))) & 15u;
}

fn contact_colour(base: vec3<f32>, level: u32) -> vec3<f32> {
    if (level == 0u) {
        return base;
    }
    let t = f32(min(level, PRESS_LEVELS) - 1u) / f32(PRESS_LEVELS - 1u);
    return mix(frame.highlight.rgb, PRESSED_DEEP, t);
}
@group(1) @binding(0) var shadow_map: texture_depth_2d;

override DEPTH_CUE: bool = false;
override GHOST: bool = false;

// Whether mono view-space depth `z` lies outside the clipping slab (always
// false with the slab off).
fn slab_cut(z: f32) -> bool {
    return frame.slab.z > 0.5 && (z > frame.slab.x || z < frame.slab.y);
}

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
    var body = u32(atom.color_body.w);
    var r = atom.pos_radius.w;
    out.color = contact_colour(atom.color_body.rgb, highlight_level(ii));
    if (GHOST) {
        body = u32(frame.ghost.w);
        r = r * 0.98;
        out.color = frame.ghost.rgb;
    }
    let c = (model_view[body] * vec4<f32>(atom.pos_radius.xyz, 1.0)).xyz - frame.eye.xyz;
    let d = length(c);
    out.centre = c;
    out.radius = r;
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

struct Hit {
    point: vec3<f32>,
    normal: vec3<f32>,
    dir: vec3<f32>,
};

// The eye ray's first hit on the sphere, or discard.
fn ray_cast(in: VsOut) -> Hit {
    let dir = normalize(in.view_pos);
    let b = dot(dir, in.centre);
    let disc = b * b - (dot(in.centre, in.centre) - in.radius * in.radius);
    if (disc < 0.0) {
        discard;
    }
    let t = b - sqrt(disc);
    let hit = dir * t;
    let z = hit.z + frame.eye.z;
    if (slab_cut(z)) {
        // Beyond the far plane the whole visible sphere is: nothing.
        // In front of the near plane: the cap where the ray crosses that
        // plane inside the sphere, facing the eye, or nothing.
        let t_cap = (frame.slab.x - frame.eye.z) / dir.z;
        if (z < frame.slab.y || !(t_cap <= b + sqrt(disc))) {
            discard;
        }
        return Hit(dir * t_cap, vec3<f32>(0.0, 0.0, 1.0), dir);
    }
    return Hit(hit, normalize(hit - in.centre), dir);
}

// Shades a hit with the share `sun` (0..1) of direct light reaching it.
fn shade(in: VsOut, h: Hit, sun: f32) -> FsOut {
    var out: FsOut;
    let l = frame.light.xyz;
    let diffuse = max(dot(h.normal, l), 0.0) * sun;
    let half_way = normalize(l - h.dir);
    let spec = pow(max(dot(h.normal, half_way), 0.0), 40.0) * 0.35 * sun;
    let ambient = frame.light.w;
    var color = in.color * (ambient + (1.0 - ambient) * diffuse) + vec3<f32>(spec);
    if (DEPTH_CUE) {
        let t = clamp((-h.point.z - frame.fog.x) / max(frame.fog.y - frame.fog.x, 1e-3), 0.0, 1.0);
        color = mix(color, frame.background.rgb, t * frame.fog.z);
    }
    out.color = vec4<f32>(color, 1.0);
    let clip = frame.proj * vec4<f32>(h.point, 1.0);
    out.depth = clip.z / clip.w;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> FsOut {
    return shade(in, ray_cast(in), 1.0);
}

// Share of the light reaching mono-view point `p` (3×3 percentage-closer filter).
fn sunlight(p: vec3<f32>, n: vec3<f32>) -> f32 {
    // Push the lookup off the surface along its normal against acne.
    let lp = (frame.light_view * vec4<f32>(p + n * frame.shadow.w, 1.0)).xyz;
    let size = frame.shadow_b.x;
    let uv = vec2<f32>(lp.x, -lp.y) / frame.shadow.x * 0.5 + 0.5;
    let depth = (frame.shadow.y - lp.z) / frame.shadow.z;
    let base = vec2<i32>(floor(uv * size));
    let top = i32(size) - 1;
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let q = clamp(base + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(top));
            let occluder = textureLoad(shadow_map, q, 0);
            lit += select(0.0, 1.0, depth <= occluder);
        }
    }
    return 1.0 - frame.shadow_b.y * (1.0 - lit / 9.0);
}

@fragment
fn fs_shadowed(in: VsOut) -> FsOut {
    let h = ray_cast(in);
    return shade(in, h, sunlight(h.point + frame.eye.xyz, h.normal));
}

struct LightOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) light_pos: vec2<f32>,
    @location(1) @interpolate(flat) centre: vec3<f32>,
    @location(2) @interpolate(flat) radius: f32,
    // The atom's centre in the mono view space (for the slab).
    @location(3) @interpolate(flat) view_centre: vec3<f32>,
};

// The shadow map: atoms seen from the light, orthographic, so each quad is
// square in light space and each ray runs along −z.
@vertex
fn vs_light(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> LightOut {
    var out: LightOut;
    let atom = atoms[ii];
    let body = u32(atom.color_body.w);
    let view = model_view[body] * vec4<f32>(atom.pos_radius.xyz, 1.0);
    let c = (frame.light_view * view).xyz;
    let r = atom.pos_radius.w;
    let p = c.xy + CORNERS[vi] * r * 1.02;
    out.light_pos = p;
    out.centre = c;
    out.radius = r;
    out.view_centre = view.xyz;
    // Depth of the quad is irrelevant: the fragment writes the true one.
    out.clip = vec4<f32>(p / frame.shadow.x, 0.5, 1.0);
    return out;
}

@fragment
fn fs_light(in: LightOut) -> @builtin(frag_depth) f32 {
    let d = in.light_pos - in.centre.xy;
    let h2 = in.radius * in.radius - dot(d, d);
    if (h2 < 0.0) {
        discard;
    }
    let z = in.centre.z + sqrt(h2);
    // Light space to mono view space: the transpose of the light's turn.
    let turn = mat3x3<f32>(frame.light_view[0].xyz, frame.light_view[1].xyz, frame.light_view[2].xyz);
    let v = in.view_centre + transpose(turn) * (vec3<f32>(in.light_pos, z) - in.centre);
    if (slab_cut(v.z)) {
        discard;
    }
    return clamp((frame.shadow.y - z) / frame.shadow.z, 0.0, 1.0);
}
