//! Writing samples and voxel maps: CSV, PLY and JSON.

use crate::{ReachableSet, Sampling, TaskSpace, VoxelMap};
use kinetree_kinematics::spatial::DVec3;
use std::io::{self, BufWriter, Write};

impl ReachableSet {
    /// Writes the samples as CSV: a header `x,y,z,manipulability` (plus `,qx,qy,qz,qw` with
    /// [`TaskSpace::Pose`]) and one line per sample, in metres, in sample order.
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_csv<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        write!(out, "x,y,z,manipulability")?;
        if self.task == TaskSpace::Pose {
            write!(out, ",qx,qy,qz,qw")?;
        }
        writeln!(out)?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(out, "{},{},{},{}", p.x, p.y, p.z, self.manipulability[i])?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, ",{},{},{},{}", o.x, o.y, o.z, o.w)?;
            }
            writeln!(out)?;
        }
        out.flush()
    }

    /// Writes the samples as an ASCII PLY point cloud: vertices `x y z` (metres) with a scalar
    /// property `manipulability` (plus `qx qy qz qw` with [`TaskSpace::Pose`]), all `double`.
    /// Point-cloud viewers (CloudCompare, MeshLab, ParaView) colour by the scalar.
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_ply<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        writeln!(out, "ply\nformat ascii 1.0")?;
        writeln!(
            out,
            "comment kinetree reachable workspace of frame {} ({} task, {})",
            self.frame.replace(['\n', '\r'], " "),
            self.task.name(),
            sampling_text(self.sampling)
        )?;
        writeln!(out, "element vertex {}", self.len())?;
        let mut properties = vec!["x", "y", "z", "manipulability"];
        if self.task == TaskSpace::Pose {
            properties.extend(["qx", "qy", "qz", "qw"]);
        }
        for p in properties {
            writeln!(out, "property double {p}")?;
        }
        writeln!(out, "end_header")?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(out, "{} {} {} {}", p.x, p.y, p.z, self.manipulability[i])?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, " {} {} {} {}", o.x, o.y, o.z, o.w)?;
            }
            writeln!(out)?;
        }
        out.flush()
    }

    /// Writes the samples as one JSON object: `frame`, `task`, `sampling`, `joints`, `count`,
    /// `bounds` (`min`, `max`), `columns` (the names of each sample's entries) and `samples`, an
    /// array of `[x, y, z, manipulability]` (plus `qx, qy, qz, qw` with [`TaskSpace::Pose`]).
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_json<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        let v = |v: DVec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
        writeln!(out, "{{")?;
        writeln!(out, "  \"frame\": {},", json_string(&self.frame))?;
        writeln!(out, "  \"task\": \"{}\",", self.task.name())?;
        let sampling = match self.sampling {
            Sampling::Grid { per_coordinate } => {
                format!("{{\"kind\": \"grid\", \"per_coordinate\": {per_coordinate}}}")
            }
            Sampling::Random { samples, seed } => {
                format!("{{\"kind\": \"random\", \"samples\": {samples}, \"seed\": {seed}}}")
            }
        };
        writeln!(out, "  \"sampling\": {sampling},")?;
        let joints: Vec<String> = self.joints.iter().map(|j| json_string(j)).collect();
        writeln!(out, "  \"joints\": [{}],", joints.join(", "))?;
        writeln!(out, "  \"count\": {},", self.len())?;
        writeln!(
            out,
            "  \"bounds\": {{\"min\": {}, \"max\": {}}},",
            v(self.bounds.min),
            v(self.bounds.max)
        )?;
        let columns = match self.task {
            TaskSpace::Position => r#"["x", "y", "z", "manipulability"]"#,
            TaskSpace::Pose => r#"["x", "y", "z", "manipulability", "qx", "qy", "qz", "qw"]"#,
        };
        writeln!(out, "  \"columns\": {columns},")?;
        writeln!(out, "  \"samples\": [")?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(
                out,
                "    [{}, {}, {}, {}",
                p.x, p.y, p.z, self.manipulability[i]
            )?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, ", {}, {}, {}, {}", o.x, o.y, o.z, o.w)?;
            }
            let comma = if i + 1 < self.len() { "," } else { "" };
            writeln!(out, "]{comma}")?;
        }
        writeln!(out, "  ]\n}}")?;
        out.flush()
    }
}

fn sampling_text(s: Sampling) -> String {
    match s {
        Sampling::Grid { per_coordinate } => format!("grid of {per_coordinate} per coordinate"),
        Sampling::Random { samples, seed } => format!("{samples} random samples, seed {seed}"),
    }
}

fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

impl VoxelMap {
    /// Writes the voxels hit as CSV: a header `x,y,z,count,max_manipulability,mean_manipulability`
    /// and one line per voxel (its centre in metres), sorted as [`VoxelMap::voxels`].
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_csv<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        writeln!(out, "x,y,z,count,max_manipulability,mean_manipulability")?;
        for (k, s) in self.voxels() {
            let c = self.center_of(k);
            writeln!(
                out,
                "{},{},{},{},{},{}",
                c.x, c.y, c.z, s.count, s.max_manipulability, s.mean_manipulability
            )?;
        }
        out.flush()
    }
}
