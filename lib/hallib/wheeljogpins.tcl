# wheeljogpins.tcl: turns on the counts-based (MPG wheel) jog inputs of
# every axis letter and of joints 0 to 8, all with one scale.
#   HALFILE = LIB:wheeljogpins.tcl         scale 1
#   HALFILE = LIB:wheeljogpins.tcl 0.1     scale 0.1 (machine units per count)
# Letters and joints the machine does not have are passed over: a setp on
# a pin that does not exist is caught and ignored.

set wheel_scale 1
if {[llength $::argv] == 1} {
  set wheel_scale [lindex $::argv 0]
}
foreach letter {x y z a b c u v w} {
  catch {setp axis.$letter.jog-enable 1}
  catch {setp axis.$letter.jog-scale $wheel_scale}
}
for {set j 0} {$j < 9} {incr j} {
  catch {setp joint.$j.jog-enable 1}
  catch {setp joint.$j.jog-scale $wheel_scale}
}
