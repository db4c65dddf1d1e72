"""The regression models, lowest numerical layer: the RBF kernel (``kernels``), Cholesky factors and solves
with repeated rows folded exactly (``linalg``), Adam and L-BFGS-B (``optimizers``), GP and TP regression in
closed form (``processes``) and the densities' tail limits in sympy (``tails``, paper section 3.3)."""
