fn main() {
    println!("smoothtri demo: coming soon");
}
