"""The validation study of libsphsolid (docs/validation.md) and its
finite-element reference.  Run from a checkout:

    python -m validation paper [--out docs/validation] [--quick]

or ``sphsolid study paper`` from the checkout's root.  Not part of the
installed ``sphsolid`` package: it is orchestration over the package and
the library, kept with the documents it regenerates."""
