//! The clips: each animation's channels and their samplers' keys, read from the JSON and
//! checked against the specification's rules (see the module documentation of [`super`]).
//!
//! Channels are read from the JSON, not through the `gltf` crate's `Channel::target`: its
//! validation does not check a channel's node index or path, and its accessors `unwrap` them.

use ::gltf::json::animation::{Interpolation as JsonInterpolation, Property};
use ::gltf::json::validation::Checked;

use super::keys::{Interpolation, Keys};
use super::numbers::{MORPH_WEIGHTS, ROTATIONS, TIMES, VEC3, read_numbers};
use super::{Channel, Clip, Msg, NodeRest, Path};
use crate::options::Budget;

/// `animation 0 "Walk"` (the name only when it has one).
fn animation_label(i: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("animation {i} {n:?}"),
        None => format!("animation {i}"),
    }
}

/// Every animation of the document as a [`Clip`], its channels checked (see [`super`]).
pub(super) fn clips(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    nodes: &[NodeRest],
    targets: &[usize],
) -> Msg<Vec<Clip>> {
    let json = doc.as_json();
    let mut out = Vec::new();
    for (a, anim) in json.animations.iter().enumerate() {
        let name = doc
            .animations()
            .nth(a)
            .and_then(|x| x.name().map(str::to_owned));
        let alabel = animation_label(a, name.as_deref());
        let mut channels = Vec::new();
        let mut used: Vec<(usize, Path)> = Vec::new();
        for (c, ch) in anim.channels.iter().enumerate() {
            let node = ch.target.node.value();
            let path = match ch.target.path {
                Checked::Valid(Property::Translation) => Path::Translation,
                Checked::Valid(Property::Rotation) => Path::Rotation,
                Checked::Valid(Property::Scale) => Path::Scale,
                Checked::Valid(Property::MorphTargetWeights) => Path::Weights,
                Checked::Invalid => {
                    return Err(format!(
                        "{alabel}, channel {c}: its target path is not valid"
                    ));
                }
            };
            let at = format!(
                "{alabel}, channel {c} (node {node} {})",
                match path {
                    Path::Translation => "translation",
                    Path::Rotation => "rotation",
                    Path::Scale => "scale",
                    Path::Weights => "weights",
                }
            );
            let Some(rest) = nodes.get(node) else {
                return Err(format!("{at}: node {node} does not exist"));
            };
            if used.contains(&(node, path)) {
                return Err(format!(
                    "{at}: a second channel of the animation targets it"
                ));
            }
            used.push((node, path));
            let width = match path {
                Path::Translation | Path::Scale => 3,
                Path::Rotation => 4,
                Path::Weights => {
                    let t = doc
                        .nodes()
                        .nth(node)
                        .and_then(|n| n.mesh())
                        .and_then(|m| targets.get(m.index()).copied())
                        .unwrap_or(0);
                    if t == 0 {
                        return Err(format!("{at}: the node has no mesh with morph targets"));
                    }
                    t
                }
            };
            if path != Path::Weights && rest.trs.is_none() {
                return Err(format!(
                    "{at}: the node has a matrix (an animated node must have translation, \
                     rotation and scale)"
                ));
            }
            let s = ch.sampler.value();
            let Some(sampler) = anim.samplers.get(s) else {
                return Err(format!("{at}: sampler {s} does not exist"));
            };
            let at = format!("{at}, sampler {s}");
            let keys = read_keys(doc, buffers, budget, sampler, path, width)
                .map_err(|m| format!("{at}: {m}"))?;
            channels.push(Channel { node, path, keys });
        }
        let duration = channels.iter().map(|c| c.keys.end()).fold(0.0, f64::max);
        out.push(Clip {
            name,
            duration,
            channels,
        });
    }
    Ok(out)
}

/// The accessor of index `i`, or a message naming `what`.
fn accessor<'a>(doc: &'a ::gltf::Document, i: usize, what: &str) -> Msg<::gltf::Accessor<'a>> {
    doc.accessors()
        .nth(i)
        .ok_or_else(|| format!("{what}: accessor {i} does not exist"))
}

/// The keys of one sampler for a channel of `path` with `width` numbers per value.
fn read_keys(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    sampler: &::gltf::json::animation::Sampler,
    path: Path,
    width: usize,
) -> Msg<Keys> {
    let interpolation = match sampler.interpolation {
        Checked::Valid(JsonInterpolation::Step) => Interpolation::Step,
        Checked::Valid(JsonInterpolation::Linear) => Interpolation::Linear,
        Checked::Valid(JsonInterpolation::CubicSpline) => Interpolation::CubicSpline,
        Checked::Invalid => return Err("its interpolation is not valid".into()),
    };
    let input = accessor(doc, sampler.input.value(), "input")?;
    let times = read_numbers(&input, &TIMES, buffers, budget).map_err(|m| format!("input {m}"))?;
    if let Some(k) = (1..times.len()).find(|&k| times[k] <= times[k - 1]) {
        return Err(format!(
            "input accessor {}: key time {k} ({} s) is not after key time {} ({} s): times must \
             increase",
            input.index(),
            times[k],
            k - 1,
            times[k - 1]
        ));
    }
    let cubic = interpolation == Interpolation::CubicSpline;
    if cubic && times.len() < 2 {
        return Err("CUBICSPLINE needs at least two keys".into());
    }
    let output = accessor(doc, sampler.output.value(), "output")?;
    let layout = match path {
        Path::Translation | Path::Scale => &VEC3,
        Path::Rotation => &ROTATIONS,
        Path::Weights => &MORPH_WEIGHTS,
    };
    let mut values =
        read_numbers(&output, layout, buffers, budget).map_err(|m| format!("output {m}"))?;
    let per_key = width * if cubic { 3 } else { 1 };
    if values.len() != times.len() * per_key {
        return Err(format!(
            "output accessor {} has {} values for {} key times ({} per key{})",
            output.index(),
            values.len() / if path == Path::Weights { 1 } else { width },
            times.len(),
            per_key / if path == Path::Weights { 1 } else { width },
            match path {
                Path::Weights => format!(" of {width} morph targets"),
                _ => String::new(),
            }
        ));
    }
    if path == Path::Rotation {
        // Rotation values are unit quaternions: renormalised (a rounded or quantised file is a
        // hair off), a zero one is an error. Tangents of the cubic spline are left as stored.
        for (k, q) in values.chunks_exact_mut(4).enumerate() {
            if cubic && k % 3 != 1 {
                continue;
            }
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(len > 0.0 && len.is_finite()) {
                return Err(format!(
                    "output accessor {}: rotation key {} is not a unit quaternion",
                    output.index(),
                    if cubic { k / 3 } else { k }
                ));
            }
            for x in q.iter_mut() {
                *x /= len;
            }
        }
    }
    Ok(Keys {
        times,
        values,
        width,
        interpolation,
        rotation: path == Path::Rotation,
    })
}
