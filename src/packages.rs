//! Where the command line looks for ROS packages: `--package-path` folders in the order
//! given, then the entries of `ROS_PACKAGE_PATH` (colon-separated, as ROS writes it),
//! both after the cell's own `package NAME at "DIR"` items (which the compiler reads).
//! The environment is read here, at the edge; the compiler is told the folders.

use cellc_compiler::CompileOptions;

use crate::args::PackageArgs;

/// The compile options of a command's package flags and the environment.
pub fn compile_options(args: &PackageArgs) -> CompileOptions {
    let ros = std::env::var("ROS_PACKAGE_PATH").unwrap_or_default();
    CompileOptions {
        package_path: search_folders(args, &ros),
    }
}

/// `--package-path` folders, then the non-empty entries of `ros_package_path`.
fn search_folders(args: &PackageArgs, ros_package_path: &str) -> Vec<String> {
    args.package_path
        .iter()
        .map(|p| p.to_string_lossy().replace('\\', "/"))
        .chain(
            ros_package_path
                .split(':')
                .filter(|e| !e.trim().is_empty())
                .map(str::to_string),
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_come_before_the_environment_in_order() {
        let args = PackageArgs {
            package_path: vec!["a".into(), "b/c".into()],
        };
        assert_eq!(
            search_folders(&args, "/opt/ros/share::/ws/src:"),
            ["a", "b/c", "/opt/ros/share", "/ws/src"]
        );
        assert!(search_folders(&PackageArgs::default(), "").is_empty());
    }
}
