//! Quiet start-up on machines without a display (servers, containers, batch jobs).
//!
//! Mesa's Vulkan device-selection layer (`VK_LAYER_MESA_device_select`, shipped with
//! `mesa-vulkan-drivers` and loaded into every Vulkan process) asks the Wayland compositor which
//! GPU drives the display. Without `XDG_RUNTIME_DIR`, libwayland prints
//! `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` once per instance, though
//! nothing is wrong: there is no display to select for, and wavetrace ranks adapters itself
//! (`context::choose`). The layer's own switch, `NODEVICE_SELECT=1`, turns it off.

/// Whether libwayland would complain: it needs `XDG_RUNTIME_DIR` set to an absolute path.
pub fn lacks_runtime_dir(xdg_runtime_dir: Option<&std::ffi::OsStr>) -> bool {
    !xdg_runtime_dir.is_some_and(|d| d.to_string_lossy().starts_with('/'))
}

/// Turns Mesa's device-selection layer off when there is no Wayland session, unless the user
/// chose a setting for it. Call first thing in `main`, before any thread exists: it sets an
/// environment variable of this process.
pub fn quiet_headless_vulkan() {
    if lacks_runtime_dir(std::env::var_os("XDG_RUNTIME_DIR").as_deref())
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY (in the 2024 edition's sense): called before any other thread is started.
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

#[cfg(test)]
mod tests {
    use super::lacks_runtime_dir;
    use std::ffi::OsStr;

    #[test]
    fn runtime_dir_must_be_absolute() {
        assert!(lacks_runtime_dir(None));
        assert!(lacks_runtime_dir(Some(OsStr::new(""))));
        assert!(lacks_runtime_dir(Some(OsStr::new("run/user/0"))));
        assert!(!lacks_runtime_dir(Some(OsStr::new("/run/user/0"))));
    }
}
