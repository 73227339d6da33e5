fn main() {
    println!("carl-spec: work in progress");
}
