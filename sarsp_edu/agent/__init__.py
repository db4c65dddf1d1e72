"""The SARSP agent (Algorithm 1, ``sarsp``), its decision rule and records (``decision``) and the functions a
decision is assembled from (``parts``)."""
