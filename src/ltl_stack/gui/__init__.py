"""rqt panels and their standalone hosts (python_qt_binding only)."""
