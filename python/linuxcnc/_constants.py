"""LinuxCNC's numbers for states, modes and commands, as its `linuxcnc`
module has them (scripts compare stat values with these)."""

# Machine states (stat.task_state; command.state).
STATE_ESTOP = 1
STATE_ESTOP_RESET = 2
STATE_OFF = 3
STATE_ON = 4

# Task modes (stat.task_mode; command.mode).
MODE_MANUAL = 1
MODE_AUTO = 2
MODE_MDI = 3

# Interpreter states (stat.interp_state).
INTERP_IDLE = 1
INTERP_READING = 2
INTERP_PAUSED = 3
INTERP_WAITING = 4

# Execution states (stat.exec_state).
EXEC_ERROR = 1
EXEC_DONE = 2
EXEC_WAITING_FOR_MOTION = 3
EXEC_WAITING_FOR_MOTION_QUEUE = 4
EXEC_WAITING_FOR_IO = 5
EXEC_WAITING_FOR_MOTION_AND_IO = 7
EXEC_WAITING_FOR_DELAY = 8
EXEC_WAITING_FOR_SYSTEM_CMD = 9
EXEC_WAITING_FOR_SPINDLE_ORIENTED = 10

# Command status (stat.state; command.wait_complete).
RCS_DONE = 1
RCS_EXEC = 2
RCS_ERROR = 3

# command.auto.
AUTO_RUN = 0
AUTO_PAUSE = 1
AUTO_RESUME = 2
AUTO_STEP = 3
AUTO_REVERSE = 4
AUTO_FORWARD = 5

# command.jog.
JOG_STOP = 0
JOG_CONTINUOUS = 1
JOG_INCREMENT = 2

# command.spindle.
SPINDLE_FORWARD = 1
SPINDLE_REVERSE = -1
SPINDLE_OFF = 0
SPINDLE_INCREASE = 10
SPINDLE_DECREASE = 11
SPINDLE_CONSTANT = 12

# command.brake.
BRAKE_RELEASE = 0
BRAKE_ENGAGE = 1

# command.flood and command.mist.
FLOOD_OFF = 0
FLOOD_ON = 1
MIST_OFF = 0
MIST_ON = 1

# Kinds of error_channel messages.
NML_ERROR = 1
NML_TEXT = 2
NML_DISPLAY = 3
OPERATOR_ERROR = 11
OPERATOR_TEXT = 12
OPERATOR_DISPLAY = 13

# stat.motion_mode.
TRAJ_MODE_FREE = 1
TRAJ_MODE_COORD = 2
TRAJ_MODE_TELEOP = 3

# stat.motion_type.
MOTION_TYPE_TRAVERSE = 1
MOTION_TYPE_FEED = 2
MOTION_TYPE_ARC = 3
MOTION_TYPE_TOOLCHANGE = 4
MOTION_TYPE_PROBING = 5
MOTION_TYPE_INDEXROTARY = 6

# stat.kinematics_type.
KINEMATICS_IDENTITY = 1
KINEMATICS_FORWARD_ONLY = 2
KINEMATICS_INVERSE_ONLY = 3
KINEMATICS_BOTH = 4

# Joint types.
LINEAR = 1
ANGULAR = 2

# Sizes of the status lists.
MAX_AXIS = 9
MAX_JOINTS = 16
