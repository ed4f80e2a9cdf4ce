# basic_sim.tcl: a simulated machine made from the INI file alone, with
# velocity/acceleration signals (ddts), simulated home switches, the
# manual tool change dialog and a simulated spindle. Each can be left out:
#   [HAL]HALFILE = LIB:basic_sim.tcl [-no_make_ddts] [-no_simulated_home]
#                  [-no_use_hal_manualtoolchange] [-no_sim_spindle]
# The joints and coordinates come from [KINS]JOINTS and [TRAJ]COORDINATES,
# the thread periods from [EMCMOT]SERVO_PERIOD and BASE_PERIOD.

source [file join $::env(HALLIB_DIR) sim_lib.tcl]

check_ini_items
set axes [get_traj_coordinates]
set number_of_joints [lindex $::KINS(JOINTS) 0]
set base_period 0
if {[info exists ::EMCMOT(BASE_PERIOD)]} {
  set base_period [lindex $::EMCMOT(BASE_PERIOD) 0]
}
# [EMCMOT]EMCMOT may carry motmod's own parameters
# (motmod unlock_joints_mask=0x10): core_sim takes the INI's list whole
# and splits its first entry into the module and its parameters.
set emcmot motmod
if {[info exists ::EMCMOT(EMCMOT)]} {
  set emcmot $::EMCMOT(EMCMOT)
}
core_sim $axes $number_of_joints [lindex $::EMCMOT(SERVO_PERIOD) 0] $base_period $emcmot

proc wanted {option} {
  return [expr {[lsearch -nocase $::argv $option] < 0}]
}
if {[wanted -no_make_ddts]} {make_ddts $number_of_joints}
if {[wanted -no_simulated_home]} {simulated_home $number_of_joints}
if {[wanted -no_use_hal_manualtoolchange]} {use_hal_manualtoolchange}
if {[wanted -no_sim_spindle]} {sim_spindle}
