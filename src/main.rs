fn main() {
    println!("ridgeline: not yet");
}
