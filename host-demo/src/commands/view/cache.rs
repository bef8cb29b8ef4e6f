//! The viewer's scenes: built on first use by precision and seams, and after a pose of an
//! animation made from the previous pose's ([`scene_of_pose`]).

use std::any::Any;
use std::collections::HashMap;
use std::rc::Rc;

use smoothtri::LineField;
use smoothtri_io::Mesh;

use crate::commands::render::{Note, build_scene};
use crate::error::Result;
use crate::tracer::{Prec, Precision, Scene};

/// The scenes built so far, by precision and seams (built on first use), and those of the
/// previous pose of an animation (what the next pose's scene is made from).
#[derive(Default)]
pub(super) struct Scenes {
    built: HashMap<(Precision, bool), Rc<dyn Any>>,
    previous: HashMap<(Precision, bool), Rc<dyn Any>>,
    /// Whether the note about skipped triangles was printed.
    noted: bool,
}

impl Scenes {
    /// The scene of `mesh` in precision `F` on `field`, with seams when `seams`: the one built
    /// before, or one made now (from the previous pose's, [`scene_of_pose`]).
    pub(super) fn get<F: Prec>(
        &mut self,
        mesh: &Mesh,
        field: LineField,
        seams: bool,
    ) -> Result<Rc<Scene<F>>> {
        let key = (F::PRECISION, seams);
        if let Some(s) = self
            .built
            .get(&key)
            .and_then(|s| Rc::clone(s).downcast::<Scene<F>>().ok())
        {
            return Ok(s);
        }
        let note = Note {
            skipped: !std::mem::replace(&mut self.noted, true),
            timing: false,
        };
        let previous = self
            .previous
            .remove(&key)
            .and_then(|s| s.downcast::<Scene<F>>().ok())
            .and_then(|s| Rc::try_unwrap(s).ok());
        let scene = Rc::new(scene_of_pose::<F>(previous, mesh, note, field, seams)?);
        self.built.insert(key, Rc::clone(&scene) as Rc<dyn Any>);
        Ok(scene)
    }

    /// The mesh moved: the scenes built so far become the previous pose's.
    pub(super) fn posed(&mut self) {
        self.previous.clear();
        self.previous.extend(self.built.drain());
    }
}

/// The scene of a posed `mesh` in precision `F` (on `field`, with seams when `seams`), given
/// the scene of the previous pose of the same animation when there is one (same triangles,
/// same options): the one place where an animation turns posed vertices into a scene. The
/// previous scene is updated in place ([`Scene::update`]); without one, or where the update
/// refuses the vertices, the scene is built afresh (as `render` builds a scene).
pub fn scene_of_pose<F: Prec>(
    previous: Option<Scene<F>>,
    mesh: &Mesh,
    note: Note,
    field: LineField,
    seams: bool,
) -> Result<Scene<F>> {
    if let Some(mut scene) = previous
        && scene.update(mesh, field, seams).is_ok()
    {
        if note.timing {
            eprintln!("update ({}): {}", F::PRECISION, scene.timing_line());
        }
        return Ok(scene);
    }
    build_scene::<F>(mesh, note, field, seams)
}
