//! What the command line chooses about ray queries: the surface a ray meets ([`Mode`]), the line
//! field the patches are built on ([`Field`]) and the normal the smooth mode shades with
//! ([`Normals`]).

/// How primary and shadow rays meet the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Mode {
    /// The smooth patches (the core's kernel).
    Smooth,
    /// Flat triangles, face normals.
    Flat,
    /// Flat triangles, interpolated vertex normals (Phong shading).
    Phong,
    /// Phong tessellation (Boubekeur & Alexa 2008, α = 3/4), traced exactly
    /// ([`crate::peers`]; `render` and `trace` only).
    PhongTess,
    /// Nagata patches (Nagata 2005), traced exactly ([`crate::peers`]; `render` and `trace`
    /// only).
    Nagata,
}

impl Mode {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Smooth => "smooth",
            Mode::Flat => "flat",
            Mode::Phong => "phong",
            Mode::PhongTess => "phong-tess",
            Mode::Nagata => "nagata",
        }
    }
}

/// The line field the patches are built on (`--field`; [`smoothtri::LineField`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Field {
    /// The paper's field (`di = ni / (ni·Nf)`): the reference construction. Neighbours' edge
    /// curves part where a face sees its vertex normals at unequal angles.
    #[default]
    Face,
    /// The shared field (lines along the vertex normals): neighbours' edge curves meet.
    Vertex,
}

impl From<Field> for smoothtri::LineField {
    fn from(f: Field) -> Self {
        match f {
            Field::Face => smoothtri::LineField::Face,
            Field::Vertex => smoothtri::LineField::Vertex,
        }
    }
}

/// Which normal the smooth mode shades with (`render --normals`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Normals {
    /// The seamless shading normal ([`smoothtri::mesh::Seam::correct`]): continuous across shared
    /// edges.
    #[default]
    Seamless,
    /// The exact geometric normal of the patch ([`Hit::normal`](smoothtri::Hit::normal)), which jumps across shared
    /// edges.
    Geometric,
}

impl Normals {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Normals::Seamless => "seamless",
            Normals::Geometric => "geometric",
        }
    }
}
