// Fairway 3D view: shaded surfaces, isophotes, reflection lines, depth-tested
// lines, and the blit of the offscreen image into egui's render pass.

struct Uniforms {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // light direction (unit, towards the light), world
    light: vec4<f32>,
    // zebra: reflected rays are measured by their angle around axis_a
    // (atan2 of the components along axis_b and axis_c)
    axis_b: vec4<f32>,
    axis_c: vec4<f32>,
    // x: mode (0 shaded, 1 isophotes, 2 zebra), y: stripe width (radians),
    // z: line depth pull (NDC), w: unused
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

struct VIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_surface(v: VIn) -> VOut {
    var o: VOut;
    o.clip = u.view_proj * vec4<f32>(v.pos, 1.0);
    o.world = v.pos;
    o.normal = v.normal;
    o.color = v.color;
    return o;
}

@vertex
fn vs_line(v: VIn) -> VOut {
    var o: VOut;
    var c = u.view_proj * vec4<f32>(v.pos, 1.0);
    // pull lines slightly towards the eye so they win against the surface
    // they lie on
    c.z = c.z - u.params.z * c.w;
    o.clip = c;
    o.world = v.pos;
    o.normal = v.normal;
    o.color = v.color;
    return o;
}

@fragment
fn fs_line(i: VOut) -> @location(0) vec4<f32> {
    return i.color;
}

// Anti-aliased black/white stripes of the quantity `s` (one stripe per unit).
fn stripes(s: f32) -> f32 {
    let t = abs(fract(s * 0.5) * 2.0 - 1.0);
    let w = max(fwidth(s), 1e-4);
    return smoothstep(0.5 - w, 0.5 + w, t);
}

@fragment
fn fs_surface(i: VOut) -> @location(0) vec4<f32> {
    var n = normalize(i.normal);
    let v = normalize(u.eye.xyz - i.world);
    // two-sided: use the side facing the eye
    if (dot(n, v) < 0.0) {
        n = -n;
    }
    let l = u.light.xyz;
    let mode = u32(u.params.x + 0.5);
    let w = max(u.params.y, 1e-4);
    if (mode == 1u) {
        // isophotes: stripes of constant angle between normal and light
        let theta = acos(clamp(dot(n, l), -1.0, 1.0));
        let s = stripes(theta / w);
        return vec4<f32>(vec3<f32>(0.06 + 0.9 * s) * i.color.a, 1.0);
    }
    if (mode == 2u) {
        // reflection lines of a family of parallel light tubes along axis_a
        let r = reflect(-v, n);
        let phi = atan2(dot(r, u.axis_b.xyz), dot(r, u.axis_c.xyz));
        let s = stripes(phi / w);
        let diff = 0.75 + 0.25 * max(dot(n, l), 0.0);
        return vec4<f32>(vec3<f32>((0.06 + 0.9 * s) * diff) * i.color.a, 1.0);
    }
    let diff = max(dot(n, l), 0.0);
    let h = normalize(l + v);
    let spec = pow(max(dot(n, h), 0.0), 48.0) * 0.22;
    let base = i.color.rgb;
    // the alpha dims (another patch of the document), the surface stays opaque
    return vec4<f32>((base * (0.28 + 0.72 * diff) + vec3<f32>(spec)) * i.color.a, 1.0);
}

// ---- blit of the offscreen image ----

@group(0) @binding(0) var img: texture_2d<f32>;
@group(0) @binding(1) var smp: sampler;

struct BlitOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_blit(@builtin(vertex_index) k: u32) -> BlitOut {
    // one triangle covering the viewport
    let x = f32((k << 1u) & 2u);
    let y = f32(k & 2u);
    var o: BlitOut;
    o.clip = vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
    o.uv = vec2<f32>(x, y);
    return o;
}

@fragment
fn fs_blit(i: BlitOut) -> @location(0) vec4<f32> {
    return textureSample(img, smp, i.uv);
}

// for an sRGB framebuffer: the image holds gamma-encoded values like egui's
fn to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

@fragment
fn fs_blit_linear(i: BlitOut) -> @location(0) vec4<f32> {
    let c = textureSample(img, smp, i.uv);
    return vec4<f32>(to_linear(c.rgb), c.a);
}
