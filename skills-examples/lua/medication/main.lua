-- Medication reminders: "remind me to take my aspirin at 8 pm". The skill manager asks
-- for the medicine or the time when the user leaves them out (skill.json "question"s);
-- the skill itself asks whether a one-off time should repeat every day. Reminders are
-- robot schedules (marvin.schedule), so they survive restarts and fire even when this
-- skill is not running. Shows marvin.ask, marvin.schedule and marvin.storage.

local TITLE_PREFIX = "take your "

-- "2026-01-05T20:00" -> "8 pm", "07:30" -> "7:30 am"
local function spoken_time(at)
  local hour, minute = at:match("T(%d%d):(%d%d)")
  if not hour then return at end
  hour, minute = tonumber(hour), tonumber(minute)
  local suffix = hour < 12 and "am" or "pm"
  local h12 = hour % 12
  if h12 == 0 then h12 = 12 end
  if minute == 0 then return h12 .. " " .. suffix end
  return string.format("%d:%02d %s", h12, minute, suffix)
end

local function how_often(recurrence)
  local kind = recurrence and recurrence.kind or "once"
  if kind == "daily" then return "every day"
  elseif kind == "weekdays" then return "on weekdays"
  elseif kind == "weekly" then return "every week"
  elseif kind == "interval" then return "regularly"
  end
  return "once"
end

local function is_yes(answer)
  answer = answer:lower()
  return answer:find("^%s*yes") or answer:find("^%s*yeah") or answer:find("^%s*sure")
    or answer:find("every day") or answer:find("^%s*please")
end

local function ours(reminder)
  return reminder.title:sub(1, #TITLE_PREFIX) == TITLE_PREFIX
end

marvin.on("add", function(slots)
  local medicine = slots.medicine:gsub("^my ", "")
  local when = slots.when
  local recurrence = when.recurrence or {kind = "once"}
  if recurrence.kind == "once" then
    local answer = marvin.ask("Do you take " .. medicine .. " every day at "
      .. spoken_time(when.at) .. "?")
    if is_yes(answer) then recurrence = {kind = "daily"} end
  end
  local reminder = marvin.schedule.add{
    title = TITLE_PREFIX .. medicine,
    at = when.at,
    time_zone = when.time_zone,
    recurrence = recurrence,
  }
  -- Remember the id, so "stop the reminder for aspirin" finds it.
  marvin.storage.set("reminder:" .. medicine, reminder.id)
  marvin.say("OK, I will remind you to take " .. medicine .. " " .. how_often(recurrence)
    .. " at " .. spoken_time(reminder.at) .. ".")
end)

marvin.on("list", function()
  local now = marvin.now()
  local found = {}
  for _, reminder in ipairs(marvin.schedule.list(now, now + 8 * 24 * 3600)) do
    if ours(reminder) then
      found[#found + 1] = reminder.title:sub(#TITLE_PREFIX + 1) .. " at "
        .. spoken_time(reminder.at)
    end
  end
  if #found == 0 then
    marvin.say("I have no medicine reminders for you.")
  else
    marvin.say("You take " .. table.concat(found, ", and ") .. ".")
  end
end)

marvin.on("cancel", function(slots)
  local medicine = slots.medicine:gsub("^my ", "")
  local id = tonumber(marvin.storage.get("reminder:" .. medicine) or "")
  if id and marvin.schedule.remove(id) then
    marvin.storage.remove("reminder:" .. medicine)
    marvin.say("OK, no more reminders for " .. medicine .. ".")
  else
    marvin.say("I have no reminder for " .. medicine .. ".")
  end
end)
