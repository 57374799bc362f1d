// Shared by the full-screen passes: the screen-covering triangle and position reconstruction
// from the camera depth.

// One triangle that covers the screen.
@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// World position of pixel `pixel` with camera depth `depth`.
fn world_position(pixel: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(pixel.x * frame.view.inv_size.x * 2.0 - 1.0, 1.0 - pixel.y * frame.view.inv_size.y * 2.0);
    let world = frame.view.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
    return world.xyz / world.w;
}

// Distance from the camera along its view for a camera depth (any projection the inverse of
// which keeps x and y out of its z and w rows: perspective, orthographic, off-centre, jittered).
fn view_depth(depth: f32) -> f32 {
    let c = frame.view.depth_to_view;
    return abs((c.x * depth + c.y) / (c.z * depth + c.w + 1e-30));
}

// Clip w at a view distance: the distance in perspective, 1 in orthographic.
fn clip_w(view_distance: f32) -> f32 {
    return select(1.0, view_distance, frame.view.toward_camera.w > 0.5);
}

// True where the camera depth buffer holds its clear value: nothing was drawn.
fn is_background(depth: f32) -> bool {
    if frame.view.reversed_depth != 0u {
        return depth <= 0.0;
    }
    return depth >= 1.0;
}

// Picks the cascade (a point light: the cube face) for the pixel at `pixel` with camera depth
// `depth`: the same in every pass.
fn use_pixel_cascade(pixel: vec2<f32>, depth: f32) {
    if light_kind() == 2u {
        use_face(world_position(pixel, depth));
        return;
    }
    use_cascade(view_depth(depth), pixel_noise(pixel.yx + vec2<f32>(7.0, 13.0)));
}

// A stable per-pixel noise value in [0, 1) (interleaved gradient noise, Jimenez 2014).
fn pixel_noise(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(pixel, vec2<f32>(0.06711056, 0.00583715))));
}
