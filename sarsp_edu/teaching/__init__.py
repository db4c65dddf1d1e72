"""What the tutorials show and grade: drawings (``plotting``), the dashboards' computations (``demos``), the
redraw framework and the tutorials' dashboards (``dashboards``), tutorial 4's live run (``live``),
the exercises and their grader (``exercises``), the prose held to its outputs (``prose``), and source notebooks
to student notebooks and static pages (``course``, ``pages``)."""
