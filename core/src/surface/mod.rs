//! The surface layer (private): the construction's pieces over the plain
//! [`Shape`](crate::geometry::Shape) of one patch: edge spheres ([`sphere`]), edge curves
//! ([`edge`]), line fields ([`field`]), the surface in generic scalars ([`scalar`]) and in
//! lanes ([`lanes`]), the shell that bounds it ([`shell`]), the tighter band that culls rays ([`band`]), the
//! interval certificate ([`certify`]) and the quartic predictor of a ray's crossing
//! ([`predictor`]). Imports only `num`, `geometry` and `aabb`.

pub(crate) mod band;
pub(crate) mod certify;
pub(crate) mod edge;
pub(crate) mod field;
pub(crate) mod lanes;
pub(crate) mod predictor;
pub(crate) mod scalar;
pub(crate) mod shell;
pub(crate) mod sphere;
