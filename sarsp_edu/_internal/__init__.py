"""The package's own plumbing, no public API: atomic files and stored-result errors (``io``), argument checks
(``validation``), BLAS threads (``threads``), process pools (``parallel``), seeds to generators (``rng``), and the
old import paths (``moved``)."""
