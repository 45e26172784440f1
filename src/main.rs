use std::process::ExitCode;

fn main() -> ExitCode {
    wavetrace::gpu::headless::quiet_headless_vulkan();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = wavetrace::cli::parse();
    match wavetrace::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
