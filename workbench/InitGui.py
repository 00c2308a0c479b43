# FreeCAD's GUI start-up runs this file (exec, no __file__) with this folder on sys.path.


class CagdWorkbench(Gui.Workbench):  # noqa: F821  (Gui is FreeCADGui, given by FreeCAD)
    """CAGD: parametric Bezier, B-spline/NURBS, spline, Hermite, Coons, triangle and
    revolution objects from the cagd engine; fitting to points, rebuild, knot removal,
    degree reduction and fairing; Gordon surfaces, sweeps, blend curves and surfaces,
    surface matching; continuity check, control nets, combs."""

    MenuText = "CAGD"
    ToolTip = "Curves and surfaces from the cagd engine (Bezier, B-spline, NURBS, Coons, ...)"

    def __init__(self):
        import cagdwb
        self.__class__.Icon = cagdwb.icon("CagdWorkbench")

    def Initialize(self):
        from cagdwb import commands
        curves, surfaces, fitting, network, tools = commands.register()
        self.appendToolbar("CAGD curves", curves)
        self.appendToolbar("CAGD surfaces", surfaces)
        self.appendToolbar("CAGD fitting", fitting)
        self.appendToolbar("CAGD network", network)
        self.appendToolbar("CAGD tools", tools)
        self.appendMenu("CAGD", curves + ["Separator"] + surfaces + ["Separator"] + fitting + ["Separator"]
                        + network + ["Separator"] + tools)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def ContextMenu(self, recipient):
        from cagdwb import commands
        self.appendContextMenu("CAGD", [c.NAME for c in commands.TOOLS])

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(CagdWorkbench())  # noqa: F821
