-- Last seen: answers from the robot's memory of sightings and its event log. Shows
-- marvin.finding.sightings and marvin.finding.events (API 1.3); every marvin.vision.look
-- (and look_around) records who and what it saw, with the room when the robot knows it.

local function ago(ms)
  local minutes = ms // 60000
  if minutes < 1 then return "just now" end
  if minutes == 1 then return "a minute ago" end
  if minutes < 60 then return minutes .. " minutes ago" end
  return (minutes // 60) .. " hours ago"
end

local function capitalize(words)
  return (words:gsub("(%a)(%w*)", function(first, rest) return first:upper() .. rest end))
end

marvin.on("glance", function()
  local ok, seen = pcall(marvin.vision.look)
  if not ok then
    marvin.say("I can't see right now.")
    return
  end
  marvin.say("I see " .. #seen.faces .. " faces and " .. #seen.objects .. " things.")
end)

marvin.on("last_seen", function(slots)
  local what = slots.what:gsub("^my ", "")
  local found = marvin.finding.sightings(what)
  if #found == 0 then
    marvin.say("I haven't seen " .. what .. ".")
    return
  end
  local s = found[1]
  local name = s.kind == "person" and capitalize(s.what) or ("the " .. s.what)
  local where = s.room ~= "" and (" in the " .. s.room) or ""
  marvin.say("I saw " .. name .. where .. ", " .. ago(marvin.now() * 1000 - s.seen_unix_ms) .. ".")
end)

marvin.on("visitors", function()
  local events = marvin.finding.events("intruder")
  if #events == 0 then
    marvin.say("No visitors.")
  else
    marvin.say(#events .. " visitor" .. (#events == 1 and "" or "s") .. ": " .. events[1].message)
  end
end)
