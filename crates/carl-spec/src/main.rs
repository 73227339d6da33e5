fn main() -> std::process::ExitCode {
    carl_spec::cli::main()
}
