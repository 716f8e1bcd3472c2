//! One list per family of kinds (obstacle shapes, target shapes, rebound laws): the
//! [`kinds!`] macro turns it into everything that would otherwise repeat the list by hand.

/// The value of one variant of a family's enum, when the enum holds that variant.
pub(crate) trait Variant<E> {
    /// This variant's value in `e`, or `None` when `e` holds another.
    fn of(e: &E) -> Option<&Self>;
}

/// Declares a family of kinds from one list, each kind a type (declared in a file of its own)
/// implementing the family's trait:
///
/// ```text
/// kinds! {
///     /// Docs of the enum.
///     pub enum ObstacleShape, tagged "shape", kinds ObstacleKind, read with &Path, as dyn ObstacleGeometry {
///         /// Docs of the variant.
///         "plane" => Plane(PlaneObstacle),
///         #[cfg(test)]
///         "ledge" => Ledge(LedgeObstacle),
///     }
/// }
/// ```
///
/// generates the enum (one newtype variant per kind, serialised with its word under the tag
/// key, then its keys), the words a file uses (a [`crate::reader::Choice`] enum of the kinds),
/// the reader's dispatch (`ObstacleShape::read(kind, section, context)` calls the kind's
/// `read`), the dispatch to the trait (`as_dyn`) and [`Variant`] for each kind. A `cfg`
/// attribute on a line applies to everything generated for that kind.
macro_rules! kinds {
    (
        $(#[doc = $doc:literal])*
        pub enum $Enum:ident, tagged $tag:literal, kinds $Kind:ident, read with $Ctx:ty,
            as dyn $Trait:ident {
            $(
                $(#[doc = $vdoc:literal])*
                $(#[cfg($cfg:meta)])?
                $word:literal => $Variant:ident($Ty:ty),
            )+
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Debug, PartialEq, serde::Serialize)]
        #[serde(tag = $tag)]
        pub enum $Enum {
            $(
                $(#[doc = $vdoc])*
                $(#[cfg($cfg)])?
                #[serde(rename = $word)]
                $Variant($Ty),
            )+
        }

        #[doc = concat!("The kinds of [`", stringify!($Enum), "`], by the word of its `", $tag, "` key.")]
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub(crate) enum $Kind {
            $(
                #[doc = concat!("`", $tag, " = \"", $word, "\"`.")]
                $(#[cfg($cfg)])?
                $Variant,
            )+
        }

        impl $crate::reader::Choice for $Kind {
            const NAMES: &'static [(&'static str, Self)] = &[ $( $(#[cfg($cfg)])? ($word, $Kind::$Variant), )+ ];
        }

        impl $Enum {
            /// Reads the keys of a `kind` from `s`.
            pub(crate) fn read(
                kind: $Kind,
                s: &$crate::reader::Section<'_>,
                context: $Ctx,
            ) -> $crate::reader::Read<Self> {
                match kind {
                    $(
                        $(#[cfg($cfg)])?
                        $Kind::$Variant => <$Ty as $Trait>::read(s, context).map($Enum::$Variant),
                    )+
                }
            }

            /// Which kind this is.
            #[allow(dead_code, reason = "not every family asks")]
            pub(crate) fn kind(&self) -> $Kind {
                match self {
                    $( $(#[cfg($cfg)])? $Enum::$Variant(_) => $Kind::$Variant, )+
                }
            }

            /// This kind's behaviour.
            pub(crate) fn as_dyn(&self) -> &dyn $Trait {
                match self {
                    $( $(#[cfg($cfg)])? $Enum::$Variant(k) => k, )+
                }
            }
        }

        $(
            $(#[cfg($cfg)])?
            impl $crate::params::registry::Variant<$Enum> for $Ty {
                fn of(e: &$Enum) -> Option<&Self> {
                    match e {
                        $Enum::$Variant(k) => Some(k),
                        #[allow(unreachable_patterns, reason = "a family of one kind")]
                        _ => None,
                    }
                }
            }
        )+
    };
}

pub(crate) use kinds;
