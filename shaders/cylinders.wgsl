// Ray-cast capped cylinder impostors: bonds and hydrogen-bond dashes, one
// instanced draw for all of them.
//
// A stick joins two atoms of the sphere renderer's atom buffer (group 0,
// the same bindings as spheres.wgsl: frame uniform, atoms, model-views,
// highlight levels), so it follows its molecules' model-view matrices and
// its atoms' colours (element, contribution, contact highlight) with no
// upload of its own. It covers the part t0..t1 of the segment from atom a
// to atom b: a whole bond is 0..1, a dash of a hydrogen bond a piece of
// it. Each instance is a box around its cylinder built in the vertex
// shader (36 vertices, both faces drawn, so the eye may be anywhere
// outside the cylinder). The fragment shader intersects the eye ray with
// the exact capped cylinder, shades the hit as spheres.wgsl does and
// writes its true depth, so sticks and spheres intersect correctly and
// the screen-space pass (outlines, occlusion) sees them.
//
// Colour: a stick whose `color` word is 0 takes each half's colour from
// its atom (split at the middle of a→b); otherwise the packed RGBA8
// (linear) colour. DEPTH_CUE is the pipeline constant of spheres.wgsl.
// The frame struct is spheres.wgsl's. The clipping slab cuts sticks as it
// cuts spheres: a stick's front surface outside the slab is discarded
// (no cap: a stick is too thin for one to read).

struct Frame {
    proj: mat4x4<f32>,
    light: vec4<f32>,
    highlight: vec4<f32>,
    eye: vec4<f32>,
    fog: vec4<f32>,
    background: vec4<f32>,
    light_view: mat4x4<f32>,
    shadow: vec4<f32>,
    shadow_b: vec4<f32>,
    // x: the slab's near plane (mono view-space z), y: its far plane, z: 1 when on.
    slab: vec4<f32>,
    // rgb: the ghost's tint; w: index of its model-view matrix.
    ghost: vec4<f32>,
};

struct Atom {
    pos_radius: vec4<f32>,
    color_body: vec4<f32>,
};

struct Stick {
    // Global atom indices (into `atoms`).
    a: u32,
    b: u32,
    // The part of a→b covered.
    t0: f32,
    t1: f32,
    radius: f32,
    // Packed RGBA8 linear colour; 0: the atoms' colours.
    color: u32,
    pad0: u32,
    pad1: u32,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> atoms: array<Atom>;
@group(0) @binding(2) var<storage, read> model_view: array<mat4x4<f32>>;
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
@group(1) @binding(0) var<storage, read> sticks: array<Stick>;

override DEPTH_CUE: bool = false;

// Whether mono view-space depth `z` lies outside the clipping slab (always
// false with the slab off), as in spheres.wgsl.
fn slab_cut(z: f32) -> bool {
    return frame.slab.z > 0.5 && (z > frame.slab.x || z < frame.slab.y);
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) @interpolate(flat) p0: vec3<f32>,
    @location(2) @interpolate(flat) p1: vec3<f32>,
    @location(3) @interpolate(flat) radius: f32,
    @location(4) @interpolate(flat) color_a: vec3<f32>,
    @location(5) @interpolate(flat) color_b: vec3<f32>,
    // x, y: t0, t1 of the piece along a→b.
    @location(6) @interpolate(flat) range: vec2<f32>,
};

// The 36 corners of a box's 12 triangles: x along the axis (0 at p0, 1 at
// p1), y and z across it (±1).
const BOX = array<vec3<f32>, 36>(
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(0.0, 1.0, -1.0), vec3<f32>(0.0, 1.0, 1.0),
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(0.0, 1.0, 1.0), vec3<f32>(0.0, -1.0, 1.0),
    vec3<f32>(1.0, -1.0, -1.0), vec3<f32>(1.0, 1.0, -1.0), vec3<f32>(1.0, 1.0, 1.0),
    vec3<f32>(1.0, -1.0, -1.0), vec3<f32>(1.0, 1.0, 1.0), vec3<f32>(1.0, -1.0, 1.0),
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(1.0, -1.0, -1.0), vec3<f32>(1.0, -1.0, 1.0),
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(1.0, -1.0, 1.0), vec3<f32>(0.0, -1.0, 1.0),
    vec3<f32>(0.0, 1.0, -1.0), vec3<f32>(1.0, 1.0, -1.0), vec3<f32>(1.0, 1.0, 1.0),
    vec3<f32>(0.0, 1.0, -1.0), vec3<f32>(1.0, 1.0, 1.0), vec3<f32>(0.0, 1.0, 1.0),
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(1.0, -1.0, -1.0), vec3<f32>(1.0, 1.0, -1.0),
    vec3<f32>(0.0, -1.0, -1.0), vec3<f32>(1.0, 1.0, -1.0), vec3<f32>(0.0, 1.0, -1.0),
    vec3<f32>(0.0, -1.0, 1.0), vec3<f32>(1.0, -1.0, 1.0), vec3<f32>(1.0, 1.0, 1.0),
    vec3<f32>(0.0, -1.0, 1.0), vec3<f32>(1.0, 1.0, 1.0), vec3<f32>(0.0, 1.0, 1.0),
);

// Atom `i` in this eye's view space (the eye at the origin) and its shown colour.
fn atom_view(i: u32) -> vec3<f32> {
    let atom = atoms[i];
    let body = u32(atom.color_body.w);
    return (model_view[body] * vec4<f32>(atom.pos_radius.xyz, 1.0)).xyz - frame.eye.xyz;
}

fn atom_color(i: u32) -> vec3<f32> {
    return contact_colour(atoms[i].color_body.rgb, highlight_level(i));
}

@vertex
fn vs_stick(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let s = sticks[ii];
    let a = atom_view(s.a);
    let b = atom_view(s.b);
    let p0 = mix(a, b, s.t0);
    let p1 = mix(a, b, s.t1);
    out.p0 = p0;
    out.p1 = p1;
    out.radius = s.radius;
    out.range = vec2<f32>(s.t0, s.t1);
    if (s.color == 0u) {
        out.color_a = atom_color(s.a);
        out.color_b = atom_color(s.b);
    } else {
        let c = unpack4x8unorm(s.color).rgb;
        out.color_a = c;
        out.color_b = c;
    }
    let axis = p1 - p0;
    let len = length(axis);
    if (len < 1e-6) {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        out.view_pos = p0;
        return out;
    }
    let u = axis / len;
    var side = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(u.y) > 0.9) {
        side = vec3<f32>(1.0, 0.0, 0.0);
    }
    let v = normalize(cross(side, u));
    let w = cross(u, v);
    let k = BOX[vi];
    let r = s.radius * 1.05;
    let p = p0 - u * r + u * (len + 2.0 * r) * k.x + (v * k.y + w * k.z) * r;
    out.view_pos = p;
    out.clip = frame.proj * vec4<f32>(p, 1.0);
    return out;
}

struct FsOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_stick(in: VsOut) -> FsOut {
    // The ray starts at the box's surface point (near the cylinder, which
    // keeps f32 exact far from the eye); t may be negative there.
    let ro = in.view_pos;
    let rd = normalize(in.view_pos);
    let ba = in.p1 - in.p0;
    let oc = ro - in.p0;
    let baba = dot(ba, ba);
    let bard = dot(ba, rd);
    let baoc = dot(ba, oc);
    let k2 = baba - bard * bard;
    let k1 = baba * dot(oc, rd) - baoc * bard;
    let k0 = baba * dot(oc, oc) - baoc * baoc - in.radius * in.radius * baba;
    var t = 0.0;
    var n = vec3<f32>(0.0);
    var y = 0.0;
    var hit = false;
    let h = k1 * k1 - k2 * k0;
    if (h >= 0.0 && k2 > 1e-12) {
        let sh = sqrt(h);
        t = (-k1 - sh) / k2;
        y = baoc + t * bard;
        if (y > 0.0 && y < baba) {
            n = (oc + t * rd - ba * y / baba) / in.radius;
            hit = true;
        }
    }
    if (!hit && abs(bard) > 1e-12) {
        // The flat caps: the near one is the one the ray meets first.
        let yc = select(baba, 0.0, bard > 0.0);
        let tc = (yc - baoc) / bard;
        let q = oc + tc * rd - ba * (yc / baba);
        if (dot(q, q) <= in.radius * in.radius) {
            t = tc;
            y = yc;
            n = ba * sign(-bard) / sqrt(baba);
            hit = true;
        }
    }
    if (!hit) {
        discard;
    }
    let point = ro + rd * t;
    if (slab_cut(point.z + frame.eye.z)) {
        discard;
    }
    let along = mix(in.range.x, in.range.y, clamp(y / baba, 0.0, 1.0));
    let base = select(in.color_b, in.color_a, along < 0.5);
    let normal = normalize(n);
    let l = frame.light.xyz;
    let diffuse = max(dot(normal, l), 0.0);
    let half_way = normalize(l - rd);
    let spec = pow(max(dot(normal, half_way), 0.0), 40.0) * 0.35;
    let ambient = frame.light.w;
    var color = base * (ambient + (1.0 - ambient) * diffuse) + vec3<f32>(spec);
    if (DEPTH_CUE) {
        let f = clamp((-point.z - frame.fog.x) / max(frame.fog.y - frame.fog.x, 1e-3), 0.0, 1.0);
        color = mix(color, frame.background.rgb, f * frame.fog.z);
    }
    var out: FsOut;
    out.color = vec4<f32>(color, 1.0);
    let clip = frame.proj * vec4<f32>(point, 1.0);
    out.depth = clip.z / clip.w;
    return out;
}
