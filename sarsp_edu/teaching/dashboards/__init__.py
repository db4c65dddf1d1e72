"""Dashboards: the redraw framework (``framework``: ``Dashboard``, ``Panel``, sliders), text for the back row
(``projector``) and the tutorials' dashboards (``tutorials``)."""
