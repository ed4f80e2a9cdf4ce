# The same in Tcl: joint 2 with its own pid instance.
loadrt pid names=pid_z
addf pid_z.do-pid-calcs servo-thread
setp pid_z.FF0 1.0
setp pid_z.Pgain 0
net zcmd joint.2.motor-pos-cmd => pid_z.command
net zen joint.2.amp-enable-out => pid_z.enable
net zfb pid_z.output => joint.2.motor-pos-fb
# As under LinuxCNC's twopass.tcl, the script can ask which pass runs.
if {[namespace exists ::tp]} {
  puts stderr "joint_z.tcl: pass [::tp::passnumber]"
}
