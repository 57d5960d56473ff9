//! Meshes, read by the runtime when a build verifies (R0002), and COLLADA files, read by
//! cellc's own reader, which trusts no count.

use std::path::Path;

use super::{args, fifo, geometric, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// A sound one-joint arm (base `base`, tip `boom`).
const ARM_URDF: &str = r#"<robot name="swinger">
  <link name="base"/>
  <link name="boom"><collision><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision></link>
  <joint name="swing" type="revolute">
    <parent link="base"/><child link="boom"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>
  </joint>
</robot>
"#;

/// A geometric cell whose object is the mesh `mesh`, built (the runtime reads the mesh
/// before it verifies anything).
fn build_with_mesh(folder: &Path, mesh: &str) -> Vec<String> {
    write(folder, "r.urdf", ARM_URDF);
    let shape = format!("    shape mesh \"{mesh}\"\n");
    write(folder, "pick.cell", geometric("r.urdf", "boom", &shape));
    args(&["build", "pick.cell", "-o", "pick.json"])
}

/// A word that a mesh holds and no message may quote.
const SECRET_WORD: &str = "hunter2secret";

/// A COLLADA file with one geometry named `id` whose accessor states `count` positions
/// (its array holds 1,000), instantiated `instances` times.
fn collada(id: &str, count: &str, instances: usize) -> String {
    let values: Vec<String> = (0..3000)
        .map(|i| format!("{}", (i % 7) as f64 * 0.01))
        .collect();
    let nodes = format!("<node><instance_geometry url=\"#{id}\"/></node>").repeat(instances);
    format!(
        r##"<?xml version="1.0"?>
<COLLADA version="1.4.1"><asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="{id}"><mesh>
<source id="p"><float_array id="a" count="3000">{}</float_array>
<technique_common><accessor source="#a" count="{count}" stride="3"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>
"##,
        values.join(" ")
    )
}

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "mesh_fifo",
            setup: |f| {
                fifo(f, "part.stl");
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "mesh_empty",
            setup: |f| {
                write(f, "part.stl", "");
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                ..SMALL
            },
        },
        Case {
            name: "mesh_over_32_mib",
            setup: |f| {
                write(f, "part.stl", vec![0u8; (32 << 20) + 1]);
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                memory_mib: 256,
                ..SMALL
            },
        },
        Case {
            name: "mesh_300k_vertices",
            setup: |f| {
                let mut obj = String::new();
                for i in 0..300_000u32 {
                    let t = f64::from(i) * 0.001;
                    obj.push_str(&format!(
                        "v {:.4} {:.4} {:.4}\n",
                        t.sin(),
                        t.cos(),
                        t * 0.001
                    ));
                }
                write(f, "part.obj", obj);
                build_with_mesh(f, "part.obj")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                seconds: 30,
                ..SMALL
            },
        },
        // ---- COLLADA meshes: read by cellc's own reader, which trusts no count ----
        Case {
            name: "mesh_dae_of_garbage",
            setup: |f| {
                let bytes: Vec<u8> = (0..100_000u32)
                    .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                    .collect();
                write(f, "part.dae", bytes);
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_counts_that_lie",
            setup: |f| {
                write(f, "part.dae", collada(SECRET_WORD, "4294967295", 1));
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                never: &[SECRET_WORD],
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_instanced_past_the_budget",
            setup: |f| {
                // 1,000 positions instantiated 1,000 times: counted before computed.
                write(f, "part.dae", collada("cube", "1000", 1000));
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_nested_a_million_deep",
            setup: |f| {
                let depth = 1_000_000;
                let text = format!(
                    "<COLLADA>{}{}</COLLADA>",
                    "<node>".repeat(depth),
                    "</node>".repeat(depth)
                );
                write(f, "part.dae", text);
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                ..SMALL
            },
        },
        Case {
            name: "mesh_of_garbage",
            setup: |f| {
                let bytes: Vec<u8> = (0..100_000u32)
                    .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                    .collect();
                write(f, "part.stl", bytes);
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some(codes::verify::MODEL_UNUSABLE),
                ..SMALL
            },
        },
    ]
}
