"""GR(1) specification model, .slugsin and structured readers/writers, Structured English."""
