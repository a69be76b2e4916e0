fn main() {
    let _ = ros2_client::zenoh::ContextOptions::new();
}
