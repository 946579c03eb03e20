"""Many cams on one camshaft (issue 24; docs/machine.md): the machine file
(:mod:`.spec`), every follower on the machine's clock (:mod:`.timing`), the camshaft torque and
the flywheel (:mod:`.torque`), each cam's tool in the machine plane (:mod:`.tools`), the clearances
between tools (:mod:`.clearance`), and the machine's numbers (:mod:`.analysis`)."""
from .analysis import MachineResult, analyse_machine, clearance_section, phase_sweep_section
from .examples import MACHINES, example_machine_dict
from .spec import ClearancePair, MachineCam, MachineSection, MachineSpec, ToolOutline, load_machine, machine_from_dict
from .timing import Event, FollowerTiming, follower_timing, tool_path
from .tools import ToolDrive, outline_of, tool_drive
from .torque import cam_torque, flywheel, machine_grid, rigid_train

__all__ = ["ClearancePair", "Event", "FollowerTiming", "MACHINES", "MachineCam", "MachineResult", "MachineSection",
           "MachineSpec", "ToolDrive", "ToolOutline", "analyse_machine", "cam_torque", "clearance_section",
           "example_machine_dict", "flywheel", "follower_timing", "load_machine", "machine_from_dict", "machine_grid",
           "outline_of", "phase_sweep_section", "rigid_train", "tool_drive", "tool_path"]
