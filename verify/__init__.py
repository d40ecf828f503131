"""External references for halfspace: scipy quadrature, mpmath and scikit-fem finite elements.

Nothing here imports or calls halfspace; the Rust tests compare the library with what this writes to
datasets/. Entry point: `python -m verify {quad,fe,hyp2f1,all,check}` (see verify/README.md).
"""
