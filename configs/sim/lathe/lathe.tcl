# The lathe's machine core, in Tcl: kinematics and motion from the INI
# file, every joint's command looped back as its feedback, a simulated
# home switch per joint, the e-stop loop. Joint N drives axis letter
# N of [TRAJ]COORDINATES.

loadrt $::KINS(KINEMATICS)
loadrt [lindex $::EMCMOT(EMCMOT) 0] \
    servo_period_nsec=$::EMCMOT(SERVO_PERIOD) num_joints=$::KINS(JOINTS)
addf motion-command-handler servo-thread
addf motion-controller servo-thread

set letters [string tolower [string map {" " ""} [lindex $::TRAJ(COORDINATES) 0]]]
set switches {}
for {set j 0} {$j < $::KINS(JOINTS)} {incr j} {
    lappend switches home_[string index $letters $j]
}
loadrt comp names=[join $switches ,]

for {set j 0} {$j < $::KINS(JOINTS)} {incr j} {
    set a [string index $letters $j]
    net ${a}pos joint.$j.motor-pos-cmd => joint.$j.motor-pos-fb home_$a.in1
    # out = in1 > in0: the switch closes past +1 mm, 0.2 mm of hysteresis
    setp home_$a.in0 1.0
    setp home_$a.hyst 0.2
    net ${a}home home_$a.out => joint.$j.home-sw-in
    addf home_$a servo-thread
}

net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in
puts "lathe.tcl: [llength $switches] joints ($letters) on a [expr {$::EMCMOT(SERVO_PERIOD) / 1000}] us servo thread"
