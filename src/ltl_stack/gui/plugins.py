"""The rqt plugins: thin ``rqt_gui_py`` wrappers around the three panels (registered in plugin.xml).

rqt is imported here and nowhere else in ``ltl_stack``, so the package and the standalone hosts work
where rqt is absent; rqt imports this module when it loads one of the plugins. Arguments after
``--args`` (``rqt_gui -s ltl_stack.gui.plugins.AnalysisPlugin --args --spec S --mapping M --live``) fill
the panel's fields as the standalone hosts' do.
"""
from __future__ import annotations

from rqt_gui_py.plugin import Plugin

from ltl_stack.gui.standalone import apply_args, build_parser, make_panel


class _PanelPlugin(Plugin):
    host = ""
    title = ""

    def __init__(self, context):
        super().__init__(context)
        self.setObjectName(type(self).__name__)
        self._widget = make_panel(self.host)
        if context.serial_number() > 1:
            self._widget.setWindowTitle(f"{self.title} ({context.serial_number()})")
        else:
            self._widget.setWindowTitle(self.title)
        self._args, _unknown = build_parser(self.host).parse_known_args(context.argv())
        context.add_widget(self._widget)

    def shutdown_plugin(self):
        if hasattr(self._widget, "shutdown"):
            self._widget.shutdown()

    def save_settings(self, plugin_settings, instance_settings):
        self._widget.save_settings(instance_settings)

    def restore_settings(self, plugin_settings, instance_settings):
        self._widget.restore_settings(instance_settings)
        apply_args(self.host, self._widget, self._args)  # the command line wins over saved settings


class MappingPlugin(_PanelPlugin):
    host = "mapping_panel"
    title = "Proposition mapping"


class AnalysisPlugin(_PanelPlugin):
    host = "analysis_panel"
    title = "Conflict analysis"


class ControllerViewPlugin(_PanelPlugin):
    host = "controller_view"
    title = "Controller view"
