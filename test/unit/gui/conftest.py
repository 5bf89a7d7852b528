"""GUI unit tests run offscreen (no display); pytest-qt's qapp is created after this is imported."""
import os

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
