fn main() -> anyhow::Result<()> {
    rodlab::cli::main()
}
