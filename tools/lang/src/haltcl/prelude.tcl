# haltcl's prelude: runs in Debian's tclsh before the user's Tcl HAL file.
# It defines the `hal` command (every halcmd command, executed by the
# haltcl process that started this tclsh), the halcmd commands as Tcl
# commands of their own where Tcl has none of that name, the INI file's
# values as arrays (::SECTION(KEY), a list of every value of the key), and
# ::argv. Requests go out on fd 3 and answers come back on fd 4: a line
# with the field count (requests) or "ok N"/"err N" (answers), then each
# field as a line with its length in bytes and the UTF-8 bytes.

namespace eval ::haltcl {
    variable prelude [dict get [info frame 0] file]
    variable req [open /dev/fd/3 w]
    variable rep [open /dev/fd/4 r]
    fconfigure $req -translation binary -buffering full
    fconfigure $rep -translation binary
}

proc ::haltcl::call {args} {
    variable req
    variable rep
    set out "[llength $args]\n"
    foreach a $args {
        set b [encoding convertto utf-8 $a]
        append out "[string length $b]\n" $b
    }
    puts -nonewline $req $out
    flush $req
    if {[gets $rep header] < 0} {
        # haltcl went away: nothing more can be done.
        exit 2
    }
    lassign $header status n
    set fields {}
    for {set i 0} {$i < $n} {incr i} {
        gets $rep len
        lappend fields [encoding convertfrom utf-8 [read $rep $len]]
    }
    return [list $status $fields]
}

# The innermost script file and line that is running (not this prelude).
proc ::haltcl::where {} {
    variable prelude
    for {set level [expr {[info frame] - 1}]} {$level > 0} {incr level -1} {
        set f [info frame $level]
        if {[dict exists $f file] && [dict get $f file] ne $prelude} {
            return [list [dict get $f file] [dict get $f line]]
        }
    }
    return [list {} 0]
}

proc hal {args} {
    if {[llength $args] == 0} {
        return -code error "wrong # args: should be \"hal command ...\""
    }
    if {[lindex $args 0] eq "--commands"} {
        return $::haltcl::commands
    }
    lassign [::haltcl::where] file line
    lassign [::haltcl::call hal $file $line {*}$args] status fields
    if {$status eq "ok"} {
        return [lindex $fields 0]
    }
    return -code error -errorcode HAL [lindex $fields 0]
}

# As LinuxCNC's haltcl: setp and sets take an expression as the value.
proc setp {name value} {
    catch {set value [uplevel 1 [list expr $value]]}
    hal setp $name $value
}
proc sets {name value} {
    catch {set value [uplevel 1 [list expr $value]]}
    hal sets $name $value
}

lassign [::haltcl::call commands] _ ::haltcl::commands
# The halcmd commands made Tcl commands here (setp and sets above too).
set ::haltcl::bare {setp sets}
foreach ::haltcl::c $::haltcl::commands {
    if {[info commands ::$::haltcl::c] eq ""} {
        proc ::$::haltcl::c {args} "hal $::haltcl::c {*}\$args"
        lappend ::haltcl::bare $::haltcl::c
    }
}
unset ::haltcl::c

lassign [::haltcl::call ini] _ ::haltcl::ini
foreach {::haltcl::sec ::haltcl::key ::haltcl::val} $::haltcl::ini {
    lappend ::${::haltcl::sec}($::haltcl::key) $::haltcl::val
}
unset -nocomplain ::haltcl::ini ::haltcl::sec ::haltcl::key ::haltcl::val

# What LinuxCNC's Tcl libraries `package require`: the hal command and
# parse_ini (which here reads INI files as the launcher does, #INCLUDE
# and all, into ::SECTION(KEY) lists).
package provide Hal 1.0
proc parse_ini {filename} {
    lassign [::haltcl::call parse-ini $filename] status fields
    if {$status ne "ok"} {
        return -code error [lindex $fields 0]
    }
    foreach {sec key val} $fields {
        lappend ::${sec}($key) $val
    }
}
package provide Linuxcnc 1.0

lassign [::haltcl::call job] _ ::haltcl::job
lassign $::haltcl::job ::haltcl::script ::haltcl::prompt ::haltcl::pass
set ::argv [lrange $::haltcl::job 3 end]
# Under [HAL]TWOPASS, LinuxCNC's twopass.tcl runs the files in its ::tp
# namespace; scripts ask it which pass runs.
if {$::haltcl::pass ne ""} {
    namespace eval ::tp {
        proc passnumber {} {return $::haltcl::pass}
    }
}
set ::argc [llength $::argv]
# Pass 0 of [HAL]TWOPASS hides the bare halcmd commands, as LinuxCNC's
# twopass.tcl does: they do nothing but loadrt (gathered), loadusr (run
# now) and addf (put off to pass 1). `hal CMD` is not hidden: a script
# may save or list what pass 0 has made.
if {$::haltcl::pass eq "0"} {
    foreach ::haltcl::c $::haltcl::bare {
        if {$::haltcl::c ni {addf loadrt loadusr source list gets}} {
            proc ::$::haltcl::c {args} {return}
        }
    }
    unset ::haltcl::c
}

proc ::haltcl::repl {} {
    set cmd ""
    while 1 {
        if {$cmd eq "" && $::haltcl::prompt} {
            puts -nonewline "haltcl: "
            flush stdout
        }
        if {[gets stdin line] < 0} {
            break
        }
        append cmd $line "\n"
        if {![info complete $cmd]} {
            continue
        }
        if {[catch {uplevel #0 $cmd} r]} {
            puts stderr $r
        } elseif {$r ne ""} {
            puts $r
        }
        set cmd ""
    }
}

if {$::haltcl::script eq ""} {
    ::haltcl::repl
    exit 0
}
set ::argv0 $::haltcl::script
if {[catch {uplevel #0 [list source $::haltcl::script]} ::haltcl::msg ::haltcl::opts]} {
    if {[dict get $::haltcl::opts -errorcode] eq "HAL"} {
        puts stderr $::haltcl::msg
    } else {
        puts stderr [dict get $::haltcl::opts -errorinfo]
    }
    exit 1
}
exit 0
